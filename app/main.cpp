// The `scan2pattern` command: builds the parser from the subcommands in cmd_*.cpp, runs the
// chosen one and maps errors to exit codes. Everything a command does is a library call first.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <new>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "app/commands.h"
#include "core/error.h"

namespace {

// glibc maps every block above its (adaptive, ≤ 32 MB) threshold afresh and unmaps it on free, so
// a buffer made again at each iteration (the fit's dense Jacobian, about 35 MB at each of
// Ceres's evaluations) is zero-filled page by page every time: a tenth of a 50k run's processor
// time went to those page faults. Blocks up to 256 MB are served from the heap and reused.
void keepLargeBuffers() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  using namespace s2p;
  keepLargeBuffers();
  CLI::App app{
      "scan2pattern: sewing patterns from a 3D scan of a clothed person\n"
      "(Bang, Korosteleva and Lee, \"Estimating Garment Patterns from Static Scan Data\", "
      "CGF 2021)"};
  app.set_version_flag("--version", std::string("scan2pattern ") + S2P_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 file not found or not writable,\n"
      "4 file format (garbage, truncated, unsupported), 5 unusable input (no faces,\n"
      "non-finite coordinates, not a person), 6 topology, 7 solver failure.");
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "No progress output on stderr");

  app::Commands commands;
  app::addScanCommands(app, commands);
  app::addBodyCommand(app, commands);
  app::addDemoCommand(app, commands);
  app::addEvalCommand(app, commands);
  app::addSynthCommands(app, commands);
  app::addSegmentCommand(app, commands);
  app::addFitCommands(app, commands);
  app::addRenderViewsCommand(app, commands);
  app::addPatternCommands(app, commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(ExitCode::Usage);
  }

  Progress progress(quiet ? Progress::Mode::Silent : Progress::Mode::Auto);
  try {
    for (const app::Command& c : commands)
      if (c.cli->parsed()) return c.run(progress);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : static_cast<int>(ExitCode::Usage);
  } catch (const s2p::Error& e) {
    std::fflush(stdout);
    fmt::print(stderr, "\nscan2pattern: error: {}\n", e.what());
    return static_cast<int>(e.exitCode());
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "\nscan2pattern: error: out of memory; try a smaller or decimated scan\n");
    return static_cast<int>(ExitCode::Internal);
  } catch (const std::exception& e) {
    fmt::print(stderr, "\nscan2pattern: internal error (please report): {}\n", e.what());
    return static_cast<int>(ExitCode::Internal);
  }
  return 0;
}
