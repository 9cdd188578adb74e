// Runs the built `scan2pattern` (S2P_APP) from the CLI tests and captures what it prints.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace s2p::test {

struct CliRun {
  int code = -1;    // exit code, −1 when the command did not exit normally
  std::string out;  // stdout, and stderr unless left out
};

// Runs "scan2pattern <args>" through the shell; `args` must quote its own paths (see q).
CliRun runCli(const std::string& args, bool withStderr = true);
// A path quoted for the shell.
std::string q(const std::filesystem::path& p);
// The JSON file at p (nlohmann's exception when it is not JSON).
nlohmann::json readJson(const std::filesystem::path& p);
// Vertices of an OBJ ("v " lines).
int objVertexCount(const std::filesystem::path& p);

}  // namespace s2p::test
