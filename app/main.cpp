// The `scan2pattern` command: parses options, calls the library, maps errors to exit codes.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <fmt/format.h>

#include "core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"scan2pattern: sewing patterns from a 3D scan of a clothed person"};
  app.set_version_flag("--version", std::string("scan2pattern ") + S2P_VERSION);
  app.require_subcommand(1);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : static_cast<int>(s2p::ExitCode::Usage);
  }
  return 0;
}
