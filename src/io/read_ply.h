// A PLY reader of our own (ASCII, binary little- and big-endian): keeps the file's vertex
// order, reads per-vertex colours and integer labels (per vertex and per face), checks counts against the file size
// before allocating, and never trusts the header.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

struct PlyData {
  TriMesh mesh;               // polygons fan-triangulated, in file order
  Eigen::MatrixX3d colour;    // #V×3 sRGB in [0, 1]; 0 rows without red/green/blue
  Eigen::VectorXi labels;     // #V from an integer "label" property; empty when absent
  Eigen::VectorXi faceLabels; // #F from a face "label" property (per triangle); empty if absent
  Eigen::VectorXi faceGroup;  // #F from a face "group" property (per triangle); empty if absent
  std::vector<std::string> warnings;
};

// Missing/unreadable → IoError; not a PLY, truncated, bad counts or indices → FormatError.
// Does not check for faces or finite coordinates (readScan does).
PlyData readPly(const std::filesystem::path& path);
// Whole file as bytes. Missing or not a regular file → IoError.
std::string readFileBytes(const std::filesystem::path& path);
// The same on bytes in memory; `what` names the source in messages.
PlyData parsePly(const std::string& bytes, const std::string& what);

}  // namespace s2p
