// Texture atlas: layout invariants (every UV triangle inside its own cell, no overlaps) and
// rasterised colours that bilinear sampling returns exactly at the corners.
#include "synth/atlas.h"

#include <gtest/gtest.h>

#include <vector>

#include "core/error.h"
#include "core/shapes.h"
#include "io/image.h"

namespace s2p {
namespace {

// A colour per vertex that varies smoothly over the mesh.
Eigen::MatrixX3d vertexColours(const TriMesh& m) {
  Eigen::MatrixX3d c(m.numVertices(), 3);
  for (int v = 0; v < m.numVertices(); ++v) {
    const Eigen::RowVector3d p = m.V.row(v);
    c.row(v) << 0.5 + 0.5 * std::sin(3 * p.x()), 0.5 + 0.4 * std::cos(5 * p.y()),
        std::clamp(0.5 + 0.5 * p.z(), 0.0, 1.0);
  }
  return c;
}

TEST(Atlas, CornerSamplesEqualTheVertexColours) {
  const TriMesh m = makeIcosphere(3, 1.0);  // 1280 faces
  const Eigen::MatrixX3d vc = vertexColours(m);
  const FaceColourFn fn = [&](int f, const Eigen::Vector3d& b) -> Eigen::Vector3d {
    return (b[0] * vc.row(m.F(f, 0)) + b[1] * vc.row(m.F(f, 1)) + b[2] * vc.row(m.F(f, 2)))
        .transpose();
  };
  for (int cell : {0, 5, 9}) {  // automatic, the smallest cell for gutter 1, a larger one
    const Texture t = bakeAtlas(m.numFaces(), fn, {.cellPx = cell});
    ASSERT_EQ(t.FUV.rows(), m.numFaces());
    ASSERT_EQ(static_cast<int>(t.image.rgb.size()), t.image.width * t.image.height * 3);
    double worst = 0;
    for (int f = 0; f < m.numFaces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d uv = t.UV.row(t.FUV(f, k));
        const Eigen::Vector3d s = sampleBilinear(t.image, uv.x(), uv.y());
        worst = std::max(worst, (s - vc.row(m.F(f, k)).transpose()).cwiseAbs().maxCoeff());
      }
    EXPECT_LE(worst, 1.0 / 255 + 1e-9) << "cell " << cell;
  }
}

TEST(Atlas, TrianglesInsideTheirCellsAndCellsDisjoint) {
  for (int nf : {1, 2, 7, 1000, 1001}) {
    const AtlasLayout L = packAtlas(nf, {.cellPx = 8, .gutterPx = 2});
    std::vector<int> owner(static_cast<size_t>(L.width) * L.height, -1);
    const int cells = (nf + 1) / 2;
    for (int c = 0; c < cells; ++c) {
      const auto [x0, y0, s] = L.cellRect(c);
      ASSERT_LE(x0 + s, L.width);
      ASSERT_LE(y0 + s, L.height);
      for (int y = y0; y < y0 + s; ++y)
        for (int x = x0; x < x0 + s; ++x) {
          int& o = owner[static_cast<size_t>(y) * L.width + x];
          EXPECT_EQ(o, -1) << "cells " << o << " and " << c << " overlap";
          o = c;
        }
    }
    for (int f = 0; f < nf; ++f) {
      const auto [x0, y0, s] = L.cellRect(L.cellOf(f));
      double sum[3];
      for (int k = 0; k < 3; ++k) {
        // Back to pixel coordinates (column, row from the top).
        const double px = L.UV(L.FUV(f, k), 0) * L.width;
        const double py = (1 - L.UV(L.FUV(f, k), 1)) * L.height;
        // Inside the cell with the gutter all around.
        EXPECT_GE(px, x0 + L.gutterPx + 0.5 - 1e-9);
        EXPECT_LE(px, x0 + s - L.gutterPx - 0.5 + 1e-9);
        EXPECT_GE(py, y0 + L.gutterPx + 0.5 - 1e-9);
        EXPECT_LE(py, y0 + s - L.gutterPx - 0.5 + 1e-9);
        // Sum of local column and row-from-bottom: the lower triangle stays at or below s − 2,
        // the upper one at or above s: the two triangles of a cell are a pixel apart.
        sum[k] = (px - x0 - 0.5) + (y0 + s - py - 0.5);
      }
      for (double v : sum) {
        if (f % 2 == 0)
          EXPECT_LE(v, s - 2 + 1e-9);
        else
          EXPECT_GE(v, s - 1e-9);
      }
    }
  }
}

TEST(Atlas, GutterTakesTheClosestTriangleColour) {
  // Two faces, one colour each: every pixel of the cell is one of the two colours.
  const FaceColourFn fn = [](int f, const Eigen::Vector3d&) -> Eigen::Vector3d {
    return f == 0 ? Eigen::Vector3d(1, 0, 0) : Eigen::Vector3d(0, 0, 1);
  };
  const Texture t = bakeAtlas(2, fn, {.cellPx = 10});
  ASSERT_EQ(t.image.width, 10);
  int red = 0, blue = 0;
  for (size_t i = 0; i < t.image.rgb.size(); i += 3) {
    if (t.image.rgb[i] == 255 && t.image.rgb[i + 2] == 0) ++red;
    if (t.image.rgb[i] == 0 && t.image.rgb[i + 2] == 255) ++blue;
  }
  EXPECT_EQ(red + blue, 100);
  EXPECT_EQ(red, 55);  // x + y ≤ 9 in a 10×10 cell
}

TEST(Atlas, BadOptionsThrow) {
  EXPECT_THROW(packAtlas(10, {.cellPx = 4, .gutterPx = 1}), InputError);
  EXPECT_THROW(packAtlas(10, {.gutterPx = 0}), InputError);
  EXPECT_THROW(packAtlas(-1), InputError);
  EXPECT_THROW(packAtlas(2'000'000'000, {.cellPx = 64}), InputError);
  const AtlasLayout L = packAtlas(4);
  EXPECT_THROW(
      rasterizeAtlas(L, 5,
                     [](int, const Eigen::Vector3d&) { return Eigen::Vector3d::Zero().eval(); }),
      InputError);
}

}  // namespace
}  // namespace s2p
