#include "synth/atlas.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace s2p {
namespace {

// Corners of the two triangles of a cell in local pixel indices (column, row from the BOTTOM of
// the cell). Lower half: x + y ≤ s − 2; upper half: x + y ≥ s; pixels on x + y = s − 1 belong to
// the lower one (clamped).
std::array<Eigen::Vector2d, 3> cornersOf(int half, int s, int g) {
  const double a = g, b = s - 2 - g, c = s - 1 - g, d = g + 1;
  if (half == 0) return {Eigen::Vector2d(a, a), Eigen::Vector2d(b, a), Eigen::Vector2d(a, b)};
  return {Eigen::Vector2d(c, c), Eigen::Vector2d(d, c), Eigen::Vector2d(c, d)};
}

// Barycentric coordinates of p in a triangle, negatives clamped and renormalised.
Eigen::Vector3d clampedBary(const std::array<Eigen::Vector2d, 3>& t, const Eigen::Vector2d& p) {
  const Eigen::Vector2d e1 = t[1] - t[0], e2 = t[2] - t[0], r = p - t[0];
  const double det = e1.x() * e2.y() - e1.y() * e2.x();
  const double b1 = (r.x() * e2.y() - r.y() * e2.x()) / det;
  const double b2 = (e1.x() * r.y() - e1.y() * r.x()) / det;
  Eigen::Vector3d b(1 - b1 - b2, b1, b2);
  b = b.cwiseMax(0.0);
  return b / b.sum();
}

}  // namespace

std::array<int, 3> AtlasLayout::cellRect(int cell) const {
  return {(cell % columns) * cellPx, (cell / columns) * cellPx, cellPx};
}

AtlasLayout packAtlas(int numFaces, const AtlasOptions& options) {
  if (numFaces < 0) throw InputError("atlas: negative number of faces");
  if (options.gutterPx < 1 || options.gutterPx > 4)
    throw InputError("atlas: gutter must be 1 to 4 pixels (got " +
                     std::to_string(options.gutterPx) + ")");
  const int minCell = 3 + 2 * options.gutterPx;
  if (options.cellPx != 0 && (options.cellPx < minCell || options.cellPx > 256))
    throw InputError("atlas: cell size must be in [" + std::to_string(minCell) +
                     ", 256] pixels for a gutter of " + std::to_string(options.gutterPx));
  if (options.maxPixels <= 0) throw InputError("atlas: the pixel budget must be positive");
  AtlasLayout L;
  L.gutterPx = options.gutterPx;
  const long cells = std::max(1L, (static_cast<long>(numFaces) + 1) / 2);
  L.columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(cells))));
  const long rows = (cells + L.columns - 1) / L.columns;
  L.cellPx = options.cellPx;
  if (L.cellPx == 0) {
    const double fit =
        std::sqrt(static_cast<double>(options.maxPixels) / static_cast<double>(cells));
    L.cellPx = std::clamp(static_cast<int>(fit), minCell, 12);
  }
  const double pixels =
      static_cast<double>(L.columns) * L.cellPx * static_cast<double>(rows) * L.cellPx;
  if (pixels * 3 > 2147483647.0)
    throw InputError("atlas: " + std::to_string(numFaces) +
                     " faces need a texture over 2^31 bytes; decimate the mesh or write PLY");
  L.width = L.columns * L.cellPx;
  L.height = static_cast<int>(rows) * L.cellPx;
  L.UV.resize(3 * static_cast<Eigen::Index>(numFaces), 2);
  L.FUV.resize(numFaces, 3);
  for (int f = 0; f < numFaces; ++f) {
    const auto [x0, y0, s] = L.cellRect(L.cellOf(f));
    const auto corners = cornersOf(f % 2, s, L.gutterPx);
    for (int k = 0; k < 3; ++k) {
      const double px = x0 + corners[k].x() + 0.5;                    // from the left
      const double rowFromTop = y0 + (s - 1 - corners[k].y()) + 0.5;  // from the top
      L.UV(3 * f + k, 0) = px / L.width;
      L.UV(3 * f + k, 1) = 1.0 - rowFromTop / L.height;
      L.FUV(f, k) = 3 * f + k;
    }
  }
  return L;
}

Image rasterizeAtlas(const AtlasLayout& layout, int numFaces, const FaceColourFn& colour) {
  if (layout.FUV.rows() != numFaces)
    throw InputError("atlas: the layout has " + std::to_string(layout.FUV.rows()) +
                     " faces, the mesh " + std::to_string(numFaces));
  Image img;
  img.width = layout.width;
  img.height = layout.height;
  img.rgb.assign(static_cast<std::size_t>(img.width) * img.height * 3, 0);
  const int cells = (numFaces + 1) / 2, s = layout.cellPx, g = layout.gutterPx;
  tbb::parallel_for(0, cells, [&](int cell) {
    const auto [x0, y0, side] = layout.cellRect(cell);
    for (int half = 0; half < 2; ++half) {
      const int f = 2 * cell + half;
      if (f >= numFaces) break;
      const auto corners = cornersOf(half, s, g);
      const bool alone = 2 * cell + 1 >= numFaces;  // no upper triangle: fill the whole cell
      for (int y = 0; y < s; ++y)
        for (int x = 0; x < s; ++x) {
          const bool lower = x + y <= s - 1;
          if (!alone && lower != (half == 0)) continue;
          const Eigen::Vector3d b = clampedBary(corners, Eigen::Vector2d(x, y));
          const Eigen::Vector3d c = colour(f, b).cwiseMax(0.0).cwiseMin(1.0);
          const std::size_t row = static_cast<std::size_t>(y0 + (s - 1 - y));
          std::uint8_t* px = &img.rgb[(row * img.width + x0 + x) * 3];
          for (int k = 0; k < 3; ++k) px[k] = static_cast<std::uint8_t>(std::lround(c[k] * 255));
        }
    }
  });
  return img;
}

Texture bakeAtlas(int numFaces, const FaceColourFn& colour, const AtlasOptions& options) {
  AtlasLayout layout = packAtlas(numFaces, options);
  Texture t;
  t.image = rasterizeAtlas(layout, numFaces, colour);
  t.UV = std::move(layout.UV);
  t.FUV = std::move(layout.FUV);
  t.path = "scan.png";
  return t;
}

}  // namespace s2p
