#include "segment/isoline.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

Eigen::VectorXd linearField(const TriMesh& m, const Eigen::Vector3d& g, double c) {
  return m.V * g - Eigen::VectorXd::Constant(m.numVertices(), c);
}

TEST(Isoline, StraightLineOnGridIsOneOpenCurveOfKnownLength) {
  const TriMesh g = makeGrid(20, 10, 2.0, 1.0);
  const Isoline iso = extractIsoline(g, linearField(g, {1, 0, 0}, 0.73));
  ASSERT_EQ(iso.curves.size(), 1u);
  const IsolineCurve& c = iso.curves[0];
  EXPECT_FALSE(c.closed);
  EXPECT_EQ(c.faces.size() + 1, c.points.size());
  EXPECT_NEAR(c.length(), 1.0, 1e-12);
  for (const auto& p : c.points) {
    EXPECT_NEAR(p.position.x(), 0.73, 1e-12);
    EXPECT_NEAR((p.point.position(g) - p.position).norm(), 0, 1e-12);
  }
  // Ends on the border y = 0 and y = 1.
  EXPECT_NEAR(std::min(c.points.front().position.y(), c.points.back().position.y()), 0, 1e-12);
  EXPECT_NEAR(std::max(c.points.front().position.y(), c.points.back().position.y()), 1, 1e-12);
}

TEST(Isoline, NegativeSideLiesToTheLeft) {
  const TriMesh g = makeGrid(10, 10);  // normals +z
  const Eigen::Vector3d grad(0.6, 0.8, 0);
  const Isoline iso = extractIsoline(g, linearField(g, grad, 0.7));
  ASSERT_EQ(iso.curves.size(), 1u);
  const auto& pts = iso.curves[0].points;
  for (size_t i = 1; i < pts.size(); ++i) {
    const Eigen::Vector3d d = pts[i].position - pts[i - 1].position;
    if (d.norm() < 1e-12) continue;
    const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(d);
    EXPECT_LT(left.dot(grad), 0);  // φ decreases to the left
  }
}

TEST(Isoline, LatitudeOnSphereIsAClosedLoopAndTwoLatitudesAreTwo) {
  const TriMesh s = makeIcosphere(4);
  const Eigen::VectorXd y = s.V.col(1);
  const Isoline one = extractIsoline(s, y, 0.3);
  ASSERT_EQ(one.curves.size(), 1u);
  EXPECT_TRUE(one.curves[0].closed);
  EXPECT_EQ(one.curves[0].faces.size(), one.curves[0].points.size());
  const double circumference = 2 * M_PI * std::sqrt(1 - 0.09);
  EXPECT_NEAR(one.length(), circumference, 0.01 * circumference);
  for (const auto& p : one.curves[0].points) EXPECT_NEAR(p.position.y(), 0.3, 1e-12);

  const Eigen::VectorXd absY = y.array().abs() - 0.5;
  const Isoline two = extractIsoline(s, absY);
  ASSERT_EQ(two.curves.size(), 2u);
  for (const auto& c : two.curves) {
    EXPECT_TRUE(c.closed);
    EXPECT_NEAR(c.length(), 2 * M_PI * std::sqrt(0.75), 0.02 * 2 * M_PI * std::sqrt(0.75));
  }
}

TEST(Isoline, ZeroAtAVertexCountsAsPositive) {
  const TriMesh g = makeGrid(10, 4, 1.0, 1.0);
  const Eigen::VectorXd phi = linearField(g, {1, 0, 0}, 0.5);  // vertex column i = 5 is zero
  const Isoline iso = extractIsoline(g, phi);
  ASSERT_EQ(iso.curves.size(), 1u);
  for (const auto& p : iso.curves[0].points) EXPECT_NEAR(p.position.x(), 0.5, 1e-12);
  EXPECT_NEAR(iso.length(), 1.0, 1e-12);
  // Only edges from column 4 (negative) to column 5 (zero, positive) are crossed.
  for (const auto& p : iso.curves[0].points) EXPECT_TRUE(p.t == 0.0 || p.t == 1.0);
}

// Isolines of a field on a grid whose zero set is the line x = 0.5, except over y ∈ [0.45, 0.55]
// where it lies at x = 0.5 + bump: the gap pass's measure of how far a boundary moved.
Isoline bumpedLine(const TriMesh& g, double bump) {
  Eigen::VectorXd phi(g.numVertices());
  for (int v = 0; v < g.numVertices(); ++v) {
    const double y = g.V(v, 1);
    phi[v] = g.V(v, 0) - 0.5 - (std::abs(y - 0.5) < 0.05 + 1e-9 ? bump : 0.0);
  }
  return extractIsoline(g, phi);
}

TEST(Isoline, CurveShiftSeesAStretchThatMovedWhereTheMeanDoesNot) {
  const TriMesh g = makeGrid(200, 200, 1.0, 1.0);
  const Isoline straight = bumpedLine(g, 0.0);
  // Moved everywhere by 1 cm: every quantile is 1 cm.
  Eigen::VectorXd phi(g.numVertices());
  for (int v = 0; v < g.numVertices(); ++v) phi[v] = g.V(v, 0) - 0.51;
  const Isoline shifted = extractIsoline(g, phi);
  EXPECT_NEAR(curveShift(straight, shifted), 0.01, 1e-9);
  EXPECT_NEAR(curveShift(straight, shifted, 0.5), 0.01, 1e-9);
  // Moved 10 cm over a tenth of its length: the median is 0, the 95th percentile the bump.
  const Isoline bumped = bumpedLine(g, 0.1);
  EXPECT_NEAR(curveShift(straight, bumped, 0.5), 0.0, 1e-9);
  EXPECT_NEAR(curveShift(straight, bumped), 0.1, 0.006);
  // Symmetric, zero against itself, +∞ against nothing.
  EXPECT_DOUBLE_EQ(curveShift(bumped, straight), curveShift(straight, bumped));
  EXPECT_EQ(curveShift(straight, straight), 0.0);
  EXPECT_EQ(curveShift(straight, Isoline{}), std::numeric_limits<double>::infinity());
  // distanceToCurves: the nearest segment, not the nearest point.
  EXPECT_NEAR(distanceToCurves(Eigen::Vector3d(0.8, 0.503, 0), straight), 0.3, 1e-12);
}

TEST(Isoline, NoCrossingGivesNoCurve) {
  const TriMesh s = makeIcosphere(2);
  EXPECT_TRUE(extractIsoline(s, Eigen::VectorXd::Ones(s.numVertices())).curves.empty());
}

TEST(Isoline, BadFieldThrowsInputError) {
  const TriMesh s = makeIcosphere(1);
  EXPECT_THROW(extractIsoline(s, Eigen::VectorXd::Zero(3)), InputError);
  Eigen::VectorXd phi = s.V.col(1);
  phi[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(extractIsoline(s, phi), InputError);
}

TEST(Isoline, InconsistentOrientationThrowsTopologyError) {
  TriMesh g = makeGrid(4, 4);
  const int f = 9;
  std::swap(g.F(f, 0), g.F(f, 1));  // flip one face
  // A line crossing the flipped face and its neighbours.
  const Eigen::Vector3d c = (g.V.row(g.F(f, 0)) + g.V.row(g.F(f, 1)) + g.V.row(g.F(f, 2))) / 3;
  EXPECT_THROW(extractIsoline(g, linearField(g, {1, 0, 0}, c.x() + 1e-3)), TopologyError);
}

}  // namespace
}  // namespace s2p
