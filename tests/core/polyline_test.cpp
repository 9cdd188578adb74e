#include "core/polyline.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace s2p {
namespace {

// A circle of radius r in the xz-plane, n points, every other one pushed out by `zig` (m).
std::vector<Eigen::Vector3d> zigzagCircle(double r, int n, double zig) {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, radius = r + (i % 2 ? zig : 0.0);
    p.emplace_back(radius * std::cos(a), 0.0, radius * std::sin(a));
  }
  return p;
}

double meanRadius(const Eigen::MatrixX3d& P) {
  double sum = 0;
  for (int i = 0; i < P.rows(); ++i) sum += std::hypot(P(i, 0), P(i, 2));
  return sum / static_cast<double>(P.rows());
}

// A circle stays a circle, shrunk by R(1 − sinc(h/R)) at most (the chord's midpoints lie inside
// by less than that again).
TEST(Polyline, BoxFilterKeepsACircle) {
  const double r = 0.2, h = 0.01;
  const Eigen::MatrixX3d P = boxFilterClosedPolyline(zigzagCircle(r, 200, 0.0), h);
  for (int i = 0; i < P.rows(); ++i) {
    const double radius = std::hypot(P(i, 0), P(i, 2));
    EXPECT_LT(radius, r);
    EXPECT_GT(radius, r * std::sin(h / r) / (h / r) - 1e-4);
    EXPECT_NEAR(P(i, 1), 0, 1e-12);
  }
}

// A zigzag of two points' wavelength is averaged away with a half-width of one edge: every point
// ends within a tenth of the zigzag of the mean circle, and the length drops to the circle's.
TEST(Polyline, BoxFilterRemovesAZigzagOfTwoEdges) {
  const double r = 0.2, zig = 0.02;
  const int n = 120;
  const std::vector<Eigen::Vector3d> rim = zigzagCircle(r, n, zig);
  const double edge = (rim[1] - rim[0]).norm();
  const Eigen::MatrixX3d P = boxFilterClosedPolyline(rim, edge);
  const double mid = meanRadius(P);
  EXPECT_NEAR(mid, r + zig / 2, zig / 10);
  double length = 0, raw = 0;
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(std::hypot(P(i, 0), P(i, 2)), mid, zig / 10) << i;
    length += (P.row((i + 1) % n) - P.row(i)).norm();
    raw += (rim[(i + 1) % n] - rim[i]).norm();
  }
  EXPECT_NEAR(length, 2 * M_PI * (r + zig / 2), 0.01);
  EXPECT_GT(raw, 1.2 * length);  // what the zigzag adds
  // Too short a loop, or no width: unchanged.
  EXPECT_EQ(boxFilterClosedPolyline(rim, 0.0).row(3), rim[3].transpose());
  EXPECT_EQ(boxFilterClosedPolyline(rim, 1.0).row(3), rim[3].transpose());
}

TEST(Polyline, SharesSumToTheLength) {
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}};
  const std::vector<double> open = arcLengthShares(p, false);
  EXPECT_DOUBLE_EQ(open[0], 0.5);
  EXPECT_DOUBLE_EQ(open[1], 1.5);
  EXPECT_DOUBLE_EQ(open[2], 1.0);
  const std::vector<double> closed = arcLengthShares(p, true);
  EXPECT_NEAR(closed[0] + closed[1] + closed[2], 3 + std::sqrt(5.0), 1e-12);
}

// A speck of one point joins its neighbours; a run across the seam of a closed curve counts as
// one; a long run stays; an open curve's end run joins its only neighbour.
TEST(Polyline, ShortRunsJoinTheirLongerNeighbour) {
  const std::vector<double> share(12, 0.004);  // 4 mm a point
  std::vector<int> a = {0, 0, 0, 0, 1, 0, 0, 0, 2, 2, 2, 2};
  mergeShortRuns(a, share, false, 0.01);
  EXPECT_EQ(a, (std::vector<int>{0, 0, 0, 0, 0, 0, 0, 0, 2, 2, 2, 2}));
  // Closed: the 1s at both ends are one run of 8 mm, shorter than 10 mm, between the 0s (24 mm)
  // and the 2s (16 mm).
  std::vector<int> b = {1, 0, 0, 0, 0, 0, 0, 2, 2, 2, 2, 1};
  mergeShortRuns(b, share, true, 0.01);
  EXPECT_EQ(b, (std::vector<int>{0, 0, 0, 0, 0, 0, 0, 2, 2, 2, 2, 0}));
  std::vector<int> c = b;
  mergeShortRuns(c, share, true, 0.0);  // nothing is shorter than nothing
  EXPECT_EQ(c, b);
  std::vector<int> d = {3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  mergeShortRuns(d, share, false, 0.01);
  EXPECT_EQ(d, std::vector<int>(12, 0));
  std::vector<int> e = {1, 2};
  EXPECT_THROW(mergeShortRuns(e, share, false, 0.01), InputError);
}

}  // namespace
}  // namespace s2p
