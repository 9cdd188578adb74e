// A texture atlas for any triangle mesh: triangles packed in pairs into square cells of a grid
// (one in the lower-left half of the cell, one in the upper-right half, a diagonal band and a
// gutter between them), each corner on a pixel centre, then a colour function rasterised inside
// every triangle and, clamped to the triangle, into its gutter, so bilinear sampling at any
// corner UV returns exactly that corner's colour.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>

#include "io/scan.h"

namespace s2p {

struct AtlasOptions {
  int cellPx = 0;              // cell side in pixels (≥ 3 + 2·gutterPx); 0: the largest that
                               // keeps the image within maxPixels, at most 12
  int gutterPx = 1;            // pixels around each triangle in its cell, in [1, 4]
  long maxPixels = 8'000'000;  // budget of the automatic cell size
};

struct AtlasLayout {
  int width = 0, height = 0;  // image size in pixels
  int cellPx = 0, gutterPx = 0;
  int columns = 0;       // cells per image row; cell c at column c % columns, row c / columns
  Eigen::MatrixX2d UV;   // 3#F×2, OpenGL convention: row 3f+k is corner k of face f
  Eigen::MatrixX3i FUV;  // #F×3 rows into UV
  // Face f lies in cell f / 2: even faces in the lower-left half, odd in the upper-right half.
  int cellOf(int face) const { return face / 2; }
  // Cell rectangle in pixels: {first column, first row from the top, side}.
  std::array<int, 3> cellRect(int cell) const;
};

// Lays out `numFaces` triangles. Throws InputError on bad options or a too-large mesh for the
// image (more than 2^31 pixels).
AtlasLayout packAtlas(int numFaces, const AtlasOptions& options = {});

// Colour (sRGB in [0, 1]) of face `face` at barycentric coordinates `bary` (sum 1, ≥ 0).
using FaceColourFn = std::function<Eigen::Vector3d(int face, const Eigen::Vector3d& bary)>;

// Rasterises `colour` into the layout's image (parallel; deterministic). Every pixel of a cell
// half takes the colour at the closest barycentric point of its triangle (gutters included).
Image rasterizeAtlas(const AtlasLayout& layout, int numFaces, const FaceColourFn& colour);

// packAtlas + rasterizeAtlas as a Texture (image, UV, FUV) for writeObjTextured.
Texture bakeAtlas(int numFaces, const FaceColourFn& colour, const AtlasOptions& options = {});

}  // namespace s2p
