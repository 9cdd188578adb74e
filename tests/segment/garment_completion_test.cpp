#include "segment/garment_completion.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// A strip x ∈ [0, 1]: x < 0.5 is the visible part (fixed), the column x = 1 is the rim pulled by
// d along z; the band between must go smoothly and monotonically from 0 to d.
TEST(GarmentCompletion, BandBlendsFromFixedPartToRimTarget) {
  const TriMesh g = makeGrid(40, 10, 1.0, 0.25);
  const double d = 0.05;
  std::vector<bool> fixed(g.numVertices(), false);
  std::vector<int> rim;
  for (int v = 0; v < g.numVertices(); ++v) {
    if (g.V(v, 0) < 0.5 - 1e-9) fixed[v] = true;
    if (g.V(v, 0) > 1 - 1e-9) rim.push_back(v);
  }
  Eigen::MatrixX3d targets(static_cast<int>(rim.size()), 3);
  for (size_t i = 0; i < rim.size(); ++i)
    targets.row(static_cast<int>(i)) = g.V.row(rim[i]) + Eigen::RowVector3d(0, 0, d);
  const Eigen::MatrixX3d V = biharmonicDeformation(g, rim, targets, fixed);
  for (int v = 0; v < g.numVertices(); ++v) {
    const double x = g.V(v, 0), dz = V(v, 2) - g.V(v, 2);
    if (fixed[v]) {
      EXPECT_EQ(V.row(v), g.V.row(v));
    }
    if (x > 1 - 1e-9) {
      EXPECT_NEAR(dz, d, 1e-12);
    }
    EXPECT_GE(dz, -1e-9);
    EXPECT_LE(dz, d + 1e-9);
    EXPECT_NEAR(V(v, 0), g.V(v, 0), 1e-9);  // no in-plane motion was asked
  }
  // Monotone along x on the middle row, and convex next to the fixed side: the band leaves the
  // fixed part tangentially (an S-shaped blend), below the straight one d·(x − 0.5)/0.5.
  const int row = 5 * 41;
  for (int i = 20; i < 40; ++i) EXPECT_LE(V(row + i, 2), V(row + i + 1, 2) + 1e-12);
  for (int i = 21; i < 25; ++i) {
    EXPECT_LT(V(row + i, 2), 0.9 * d * (i - 20) / 20.0) << i;
    EXPECT_GT(V(row + i + 1, 2) - 2 * V(row + i, 2) + V(row + i - 1, 2), 0.0) << i;
  }
}

TEST(GarmentCompletion, BadInputThrows) {
  const TriMesh g = makeGrid(4, 4);
  std::vector<bool> fixed(g.numVertices(), false);
  fixed[0] = true;
  EXPECT_THROW(biharmonicDeformation(g, {0}, Eigen::MatrixX3d::Zero(1, 3), fixed), InputError);
  EXPECT_THROW(biharmonicDeformation(g, {1}, Eigen::MatrixX3d::Zero(2, 3), fixed), InputError);
  EXPECT_THROW(biharmonicDeformation(g, {1}, Eigen::MatrixX3d::Zero(1, 3), {true}), InputError);
  Eigen::MatrixX3d nan = Eigen::MatrixX3d::Zero(1, 3);
  nan(0, 0) = std::nan("");
  EXPECT_THROW(biharmonicDeformation(g, {1}, nan, fixed), InputError);
}

}  // namespace
}  // namespace s2p
