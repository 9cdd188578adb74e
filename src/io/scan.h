// A scan as read from disk: the mesh, its colours, its texture and the transform back to the
// file's frame. Produced by readScan (read_scan.h), cleaned by cleanScan (cleanup.h) and moved
// to metres / +Y up / feet on y = 0 by normalizeScan (normalize.h).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

enum class ColourSource { None, Vertex, Texture };
const char* toString(ColourSource source);

// An 8-bit RGB image kept so that results can be exported with the scan's texture.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // width·height·3, row-major, top row first
};

// Texture coordinates of the mesh: a separate UV index buffer, as in OBJ (a vertex on a UV
// seam has several UVs).
struct Texture {
  Image image;
  std::string path;    // where the image was read from
  Eigen::MatrixX2d UV;  // #UV×2, OpenGL convention: (0,0) is the bottom-left of the image
  Eigen::MatrixX3i FUV; // #F×3 rows into UV, one per face corner
};

struct Scan {
  TriMesh mesh;
  Eigen::MatrixX3d colour;  // #V×3 sRGB in [0, 1]; 0 rows when colourSource == None
  ColourSource colourSource = ColourSource::None;
  std::optional<Texture> texture;
  std::string sourcePath;  // file the scan came from (for messages)
  // Maps normalised coordinates back to the file's frame and units: p_file = toInput * p.
  // Identity until normalizeScan runs.
  Eigen::Affine3d toInputFrame = Eigen::Affine3d::Identity();
};

}  // namespace s2p
