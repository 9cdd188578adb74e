// Small file-name helpers shared by the readers and writers.
#pragma once

#include <filesystem>
#include <string>

namespace s2p {

// The extension of `path` in lower case, with its dot (".ply"); empty when there is none.
std::string lowerExtension(const std::filesystem::path& path);

}  // namespace s2p
