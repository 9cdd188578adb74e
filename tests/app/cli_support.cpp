#include "cli_support.h"

#include <sys/wait.h>

#include <cstdio>
#include <fstream>

namespace s2p::test {

CliRun runCli(const std::string& args, bool withStderr) {
  const std::string cmd =
      std::string("'") + S2P_APP + "' " + args + (withStderr ? " 2>&1" : " 2>/dev/null");
  CliRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) r.out.append(buf, n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string q(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}

nlohmann::json readJson(const std::filesystem::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

int objVertexCount(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) n += line.rfind("v ", 0) == 0;
  return n;
}

}  // namespace s2p::test
