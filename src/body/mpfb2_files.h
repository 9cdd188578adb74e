// Readers for the files of an MPFB2 / MakeHuman folder: the base OBJ, gzipped morph targets
// and JSON. Each throws IoError naming the file when it cannot be read and FormatError naming
// the file and line when its content is malformed.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace s2p {

// The MakeHuman base mesh as written: all vertices, polygon faces with their group.
struct Mpfb2Obj {
  Eigen::MatrixX3d V;                                     // #V×3, file units (decimetres)
  std::vector<std::vector<int>> faces;                    // 0-based vertex indices per polygon
  std::vector<int> faceGroup;                             // #faces, index into groups
  std::vector<std::string> groups;                        // group names in order of appearance
  std::map<std::string, std::vector<int>> groupVertices;  // group → sorted vertex ids
};
Mpfb2Obj readMpfb2Obj(const std::filesystem::path& file);

// A morph target: sparse per-vertex offsets (file units).
struct Mpfb2Target {
  std::vector<int> index;              // vertex ids
  std::vector<Eigen::Vector3d> delta;  // same length
};
// Reads `vertex dx dy dz` lines, gzipped or plain; `numVertices` bounds the indices.
Mpfb2Target readMpfb2Target(const std::filesystem::path& file, int numVertices);

// Parses a JSON file (IoError when missing, FormatError when not JSON).
nlohmann::json readJsonFile(const std::filesystem::path& file);

}  // namespace s2p
