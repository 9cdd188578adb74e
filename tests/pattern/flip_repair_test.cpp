#include "pattern/flip_repair.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

namespace s2p {
namespace {

// An n×n grid of unit-spaced vertices in the plane, two counter-clockwise triangles per cell;
// its 3D areas are all ½.
struct Grid {
  int n;
  Eigen::MatrixX2d uv;
  Eigen::MatrixX3i F;
  Eigen::VectorXd area3d;
  int at(int i, int j) const { return j * n + i; }
};

Grid makeGrid(int n) {
  Grid g{n, Eigen::MatrixX2d(n * n, 2), Eigen::MatrixX3i(2 * (n - 1) * (n - 1), 3), {}};
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) g.uv.row(g.at(i, j)) << i, j;
  int f = 0;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      g.F.row(f++) << g.at(i, j), g.at(i + 1, j), g.at(i + 1, j + 1);
      g.F.row(f++) << g.at(i, j), g.at(i + 1, j + 1), g.at(i, j + 1);
    }
  g.area3d = Eigen::VectorXd::Constant(g.F.rows(), 0.5);
  return g;
}

// Vertices that moved between two layouts.
int movedCount(const Eigen::MatrixX2d& a, const Eigen::MatrixX2d& b) {
  int count = 0;
  for (int v = 0; v < a.rows(); ++v) count += (a.row(v) - b.row(v)).norm() > 0.0;
  return count;
}

TEST(FlipRepair, AVertexPushedAcrossItsNeighbourIsPutBackAndNothingElseMoves) {
  Grid g = makeGrid(7);
  const int v = g.at(3, 3);
  g.uv.row(v) << 4.6, 3.2;  // past its right neighbour (4, 3): its faces fold
  ASSERT_GT(countInvertedFaces(g.uv, g.F), 0);
  const Eigen::MatrixX2d before = g.uv;
  const FlipRepairResult r = repairFlips(g.uv, g.F, g.area3d);
  EXPECT_GT(r.invertedBefore, 0);
  EXPECT_EQ(r.invertedAfter, 0);
  EXPECT_EQ(countInvertedFaces(g.uv, g.F), 0);
  // The vertex alone moves, into its one-ring's kernel (the square (2..4) × (2..4) here), and
  // no further than it must: it stays on the kernel's right side, near x = 4.
  EXPECT_EQ(movedCount(before, g.uv), 1);
  EXPECT_LT(g.uv(v, 0), 4.0);
  EXPECT_GT(g.uv(v, 0), 3.5);
  // Every face keeps at least a share of its area: margin 5 % of ½.
  for (int f = 0; f < g.F.rows(); ++f) EXPECT_GE(signedFaceArea(g.uv, g.F, f), 0.025 - 1e-12);
}

TEST(FlipRepair, ABoundaryVertexPulledInsideIsPutBackOutside) {
  Grid g = makeGrid(6);
  const int v = g.at(0, 2);  // on the left edge
  g.uv.row(v) << 1.5, 2.0;   // past its inner neighbour (1, 2)
  ASSERT_GT(countInvertedFaces(g.uv, g.F), 0);
  const FlipRepairResult r = repairFlips(g.uv, g.F, g.area3d);
  EXPECT_EQ(r.invertedAfter, 0);
  EXPECT_LT(g.uv(v, 0), 1.0);  // back on the outer side of (1, 2)'s column
}

TEST(FlipRepair, AFoldOfSeveralVerticesIsOpened) {
  // A 3×3 block of inner vertices mirrored across the block's centre column and shifted: every
  // vertex of the fold has an empty kernel at first, so only the ring-by-ring repair opens it.
  Grid g = makeGrid(11);
  for (int j = 4; j <= 6; ++j)
    for (int i = 4; i <= 6; ++i) g.uv.row(g.at(i, j)) << 10.0 - i + 0.3, j;
  const int foldedBefore = countInvertedFaces(g.uv, g.F);
  ASSERT_GT(foldedBefore, 4);
  const FlipRepairResult r = repairFlips(g.uv, g.F, g.area3d);
  EXPECT_EQ(r.invertedBefore, foldedBefore);
  EXPECT_EQ(r.invertedAfter, 0);
  EXPECT_EQ(countInvertedFaces(g.uv, g.F), 0);
  // The grid's outline is held: a repair opens a fold inside, it does not move the cut line.
  const Grid original = makeGrid(11);
  for (int i = 0; i < 11; ++i)
    for (int j : {0, 10}) {
      EXPECT_EQ(g.uv.row(g.at(i, j)), original.uv.row(original.at(i, j)));
      EXPECT_EQ(g.uv.row(g.at(j, i)), original.uv.row(original.at(j, i)));
    }
}

TEST(FlipRepair, TwoOutlineVerticesSwappedAcrossEachOtherAreUnfolded) {
  // Two neighbours on the grid's left edge swapped across each other, as an exact cut's corner
  // slivers fold.
  Grid g = makeGrid(8);
  g.uv.row(g.at(0, 3)) << 0.1, 4.4;
  g.uv.row(g.at(0, 4)) << 0.1, 2.6;
  ASSERT_GT(countInvertedFaces(g.uv, g.F), 0);
  const FlipRepairResult r = repairFlips(g.uv, g.F, g.area3d);
  EXPECT_EQ(r.invertedAfter, 0);
  EXPECT_EQ(countInvertedFaces(g.uv, g.F), 0);
  // Far from the fold nothing moved: the right half of the grid is as it was.
  const Grid original = makeGrid(8);
  for (int j = 0; j < 8; ++j)
    for (int i = 4; i < 8; ++i) EXPECT_EQ(g.uv.row(g.at(i, j)), original.uv.row(original.at(i, j)));
}

TEST(FlipRepair, AFlipFreeLayoutIsLeftExactlyAsItIs) {
  Grid g = makeGrid(5);
  g.uv.row(g.at(2, 2)) << 2.3, 1.9;  // distorted, not folded
  const Eigen::MatrixX2d before = g.uv;
  const FlipRepairResult r = repairFlips(g.uv, g.F, g.area3d);
  EXPECT_EQ(r.invertedBefore, 0);
  EXPECT_EQ(r.verticesMoved, 0);
  EXPECT_EQ(movedCount(before, g.uv), 0);
}

TEST(FlipRepair, AZeroAreaFaceCountsAsInvertedAndIsOpened) {
  Grid g = makeGrid(5);
  const int v = g.at(2, 2);
  g.uv.row(v) << 2.0, 3.0;  // onto its upper neighbour: the faces they share have no area
  ASSERT_GT(countInvertedFaces(g.uv, g.F), 0);
  EXPECT_EQ(repairFlips(g.uv, g.F, g.area3d).invertedAfter, 0);
}

}  // namespace
}  // namespace s2p
