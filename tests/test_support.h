// Helpers shared by the test programs.
#pragma once

#include <filesystem>
#include <string>

namespace s2p::test {

// A fresh empty directory under the system temp dir, removed when the object dies.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "s2p_test");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// Writes `bytes` to `path` (binary).
void writeFile(const std::filesystem::path& path, const std::string& bytes);
// Reads a whole file (binary).
std::string readFile(const std::filesystem::path& path);

// ../shared beside the repository (bodymodels, paper); empty when absent.
std::filesystem::path sharedDir();

}  // namespace s2p::test
