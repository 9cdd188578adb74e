#include "body/plane_section.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

constexpr double kPi = std::numbers::pi;

// Perimeter of the regular n-gon inscribed in a circle of radius r.
double inscribedPerimeter(int n, double r) {
  return 2 * n * r * std::sin(kPi / n);
}

TriMesh translated(TriMesh m, const Eigen::Vector3d& t) {
  m.V.rowwise() += t.transpose();
  return m;
}

TriMesh concat(const TriMesh& a, const TriMesh& b) {
  TriMesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, (b.F.array() + a.numVertices()).matrix();
  return m;
}

// Open prism along y (0..1) whose cross-section is a 5-pointed star: tips at radius R,
// notches at radius r.
TriMesh makeStarPrism(double R, double r) {
  const int n = 10;
  TriMesh m;
  m.V.resize(2 * n, 3);
  for (int ring = 0; ring < 2; ++ring)
    for (int s = 0; s < n; ++s) {
      const double phi = 2 * kPi * s / n, rad = s % 2 == 0 ? R : r;
      m.V.row(ring * n + s) << rad * std::sin(phi), ring, rad * std::cos(phi);
    }
  m.F.resize(2 * n, 3);
  for (int s = 0; s < n; ++s) {
    const int a = s, b = (s + 1) % n, c = a + n, d = b + n;
    m.F.row(2 * s) << a, b, d;
    m.F.row(2 * s + 1) << a, d, c;
  }
  return m;
}

TEST(PlaneSection, CylinderGivesInscribedPolygonOfThePerimeter2PiR) {
  const double r = 0.3;
  const TriMesh cyl = makeCylinder(4, 64, r, 1.0);
  const auto loops = planeSection(cyl, {0, 0.37, 0}, {0, 1, 0});
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_TRUE(loops[0].closed);
  EXPECT_EQ(loops[0].points.rows(), 2 * 64);  // one point per vertical and diagonal edge
  for (Eigen::Index i = 0; i < loops[0].points.rows(); ++i)
    EXPECT_NEAR(loops[0].points(i, 1), 0.37, 1e-12);
  // The diagonal edges cross on the chords, so both measures are exactly the 64-gon's.
  EXPECT_NEAR(convexHullPerimeter(loops[0], {0, 1, 0}), inscribedPerimeter(64, r), 1e-12);
  EXPECT_NEAR(polylineLength(loops[0]), inscribedPerimeter(64, r), 1e-12);
  EXPECT_NEAR(convexHullPerimeter(loops[0], {0, 1, 0}), 2 * kPi * r, 1e-3 * 2 * kPi * r);
  EXPECT_NEAR(enclosedArea(loops[0], {0, 1, 0}), 32 * r * r * std::sin(2 * kPi / 64), 1e-12);
}

TEST(PlaneSection, PlaneThroughARingOfVerticesStillGivesOneSimpleLoop) {
  const double r = 0.25;
  const TriMesh cyl = makeCylinder(2, 48, r, 1.0);  // ring 1 lies exactly at y = 0.5
  const auto loops = planeSection(cyl, {0, 0.5, 0}, {0, 1, 0});
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_TRUE(loops[0].closed);
  EXPECT_EQ(loops[0].points.rows(), 48);  // the ring's vertices, each once
  EXPECT_NEAR(convexHullPerimeter(loops[0], {0, 1, 0}), inscribedPerimeter(48, r), 1e-12);
}

TEST(PlaneSection, SphereAtHeightHGivesCircleOfRadiusSqrtR2MinusH2) {
  const double R = 0.8;
  const TriMesh sphere = makeIcosphere(4, R);
  for (double h : {-0.6, -0.2, 0.0, 0.31, 0.7}) {
    const auto loops = planeSection(sphere, {0, h, 0}, {0, 1, 0});
    ASSERT_EQ(loops.size(), 1u) << "h = " << h;
    EXPECT_TRUE(loops[0].closed);
    const double expected = 2 * kPi * std::sqrt(R * R - h * h);
    EXPECT_NEAR(convexHullPerimeter(loops[0], {0, 1, 0}), expected, 4e-3 * expected) << "h = " << h;
    // Inscribed polyhedron: the section lies inside the true circle.
    for (Eigen::Index i = 0; i < loops[0].points.rows(); ++i)
      EXPECT_LE(loops[0].points.row(i).norm(), R + 1e-12);
  }
  // The same with an oblique plane at distance h from the centre.
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, -0.5).normalized();
  const auto loops = planeSection(sphere, 0.4 * n, n);
  ASSERT_EQ(loops.size(), 1u);
  const double expected = 2 * kPi * std::sqrt(R * R - 0.16);
  EXPECT_NEAR(convexHullPerimeter(loops[0], n), expected, 4e-3 * expected);
}

TEST(PlaneSection, PlaneMissingTheMeshGivesNothing) {
  EXPECT_TRUE(planeSection(makeIcosphere(2, 1.0), {0, 1.5, 0}, {0, 1, 0}).empty());
}

TEST(PlaneSection, TiltedPlaneThroughCylinderGivesEllipse) {
  const double r = 0.2, a = 0.5;  // tilt angle (rad): semi-axes r and r / cos a
  const TriMesh cyl = makeCylinder(30, 128, r, 2.0);
  const Eigen::Vector3d n(0, std::cos(a), std::sin(a));
  const auto loops = planeSection(cyl, {0, 1.0, 0}, n);
  ASSERT_EQ(loops.size(), 1u);
  const double A = r / std::cos(a), B = r;
  const double hh = (A - B) * (A - B) / ((A + B) * (A + B));
  const double ramanujan = kPi * (A + B) * (1 + 3 * hh / (10 + std::sqrt(4 - 3 * hh)));
  EXPECT_NEAR(convexHullPerimeter(loops[0], n), ramanujan, 1e-3 * ramanujan);
  EXPECT_NEAR(enclosedArea(loops[0], n), kPi * A * B, 2e-3 * kPi * A * B);
}

TEST(PlaneSection, TwoDisjointCylindersGiveTwoLoopsEachAroundItsOwnAxis) {
  const TriMesh left = translated(makeCylinder(3, 40, 0.1, 1.0), {-0.3, 0, 0});
  const TriMesh right = translated(makeCylinder(3, 40, 0.15, 1.0), {0.3, 0, 0.05});
  const TriMesh both = concat(left, right);
  const Eigen::Vector3d up(0, 1, 0);
  const auto loops = planeSection(both, {0, 0.5, 0}, up);
  ASSERT_EQ(loops.size(), 2u);
  int seen = 0;
  for (const auto& loop : loops) {
    ASSERT_TRUE(loop.closed);
    const bool isLeft = loopEncloses(loop, {-0.3, 0.5, 0}, up);
    const bool isRight = loopEncloses(loop, {0.3, 0.5, 0.05}, up);
    ASSERT_NE(isLeft, isRight);
    seen |= isLeft ? 1 : 2;
    EXPECT_NEAR(convexHullPerimeter(loop, up), inscribedPerimeter(40, isLeft ? 0.1 : 0.15), 1e-12);
    EXPECT_FALSE(loopEncloses(loop, {0, 0.5, 0}, up));  // the gap between them
  }
  EXPECT_EQ(seen, 3);
}

TEST(PlaneSection, HullOfAStarSectionIsThePentagonThroughItsTips) {
  const double R = 0.2, r = 0.08;
  const TriMesh star = makeStarPrism(R, r);
  const Eigen::Vector3d up(0, 1, 0);
  const auto loops = planeSection(star, {0, 0.4, 0}, up);
  ASSERT_EQ(loops.size(), 1u);
  ASSERT_TRUE(loops[0].closed);
  EXPECT_NEAR(convexHullPerimeter(loops[0], up), inscribedPerimeter(5, R), 1e-12);
  // The curve itself follows the notches: 10 sides between radius R and r, 36° apart.
  const double side = std::sqrt(R * R + r * r - 2 * R * r * std::cos(kPi / 5));
  EXPECT_NEAR(polylineLength(loops[0]), 10 * side, 1e-12);
  EXPECT_NEAR(enclosedArea(loops[0], up), 5 * R * r * std::sin(kPi / 5), 1e-12);
  EXPECT_TRUE(loopEncloses(loops[0], {0, 0.4, 0}, up));
  // Inside the hull but in a notch: not enclosed by the curve.
  const double notchMid = 0.5 * (r + R * std::cos(kPi / 5));
  EXPECT_FALSE(loopEncloses(
      loops[0], {notchMid * std::sin(kPi / 5) * 1.6, 0.4, notchMid * std::cos(kPi / 5) * 1.6}, up));
}

TEST(PlaneSection, OpenMeshGivesOpenPolylineEndingOnTheBoundary) {
  const TriMesh grid = makeGrid(7, 5, 1.0, 1.0);  // z = 0 plane, [0,1]²
  const auto loops = planeSection(grid, {0.43, 0, 0}, {1, 0, 0});
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_FALSE(loops[0].closed);
  EXPECT_NEAR(polylineLength(loops[0]), 1.0, 1e-12);  // straight across from y = 0 to y = 1
  EXPECT_NEAR(distanceToLoop(loops[0], {0.43, 0.5, 0.2}), 0.2, 1e-12);
  EXPECT_FALSE(loopEncloses(loops[0], {0.43, 0.5, 0}, {1, 0, 0}));
}

TEST(PlaneSection, SlicerGivesTheSameAsTheOneShotFunction) {
  const TriMesh sphere = makeUvSphere(20, 30, 0.5);
  const MeshSlicer slicer(sphere);
  for (double h : {-0.3, 0.1, 0.45}) {
    const auto a = slicer.section({0, h, 0}, {0, 1, 0});
    const auto b = planeSection(sphere, {0, h, 0}, {0, 1, 0});
    ASSERT_EQ(a.size(), 1u);
    ASSERT_EQ(b.size(), 1u);
    EXPECT_EQ(a[0].points, b[0].points);
  }
}

TEST(PlaneSection, HorizontalFastPathAgreesWithTheGeneralOne) {
  // (1e-300, 1, 0) is not exactly vertical, so it takes the scan over every face.
  const TriMesh sphere = makeIcosphere(3, 0.7);
  const MeshSlicer slicer(sphere);
  for (double h : {-0.69, -0.35, 0.0, 0.123, 0.5, 0.6999}) {
    const auto fast = slicer.section({0, h, 0}, {0, 1, 0});
    const auto slow = slicer.section({0, h, 0}, {1e-300, 1, 0});
    ASSERT_EQ(fast.size(), slow.size()) << "h = " << h;
    ASSERT_EQ(fast.size(), 1u) << "h = " << h;
    EXPECT_EQ(fast[0].points.rows(), slow[0].points.rows());
    EXPECT_NEAR(polylineLength(fast[0]), polylineLength(slow[0]), 1e-12);
  }
  EXPECT_TRUE(slicer.section({0, 0.71, 0}, {0, 1, 0}).empty());
  EXPECT_TRUE(slicer.section({0, -0.71, 0}, {0, -1, 0}).empty());
}

TEST(PlaneSection, BadInputThrowsInputError) {
  const TriMesh cyl = makeCylinder(2, 8, 0.1, 1.0);
  EXPECT_THROW(planeSection(cyl, {0, 0.5, 0}, {0, 0, 0}), InputError);
  EXPECT_THROW(planeSection(cyl, {0, 0.5, 0}, {0, std::nan(""), 0}), InputError);
  EXPECT_THROW(planeSection(cyl, {0, std::nan(""), 0}, {0, 1, 0}), InputError);
  TriMesh bad = cyl;
  bad.F(3, 1) = 1000;
  EXPECT_THROW(planeSection(bad, {0, 0.5, 0}, {0, 1, 0}), InputError);
  bad = cyl;
  bad.V(2, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(planeSection(bad, {0, 0.5, 0}, {0, 1, 0}), InputError);
  EXPECT_THROW(planeSection(TriMesh{}, {0, 0.5, 0}, {0, 1, 0}), InputError);
  SectionLoop loop{Eigen::MatrixX3d::Zero(3, 3), true};
  EXPECT_THROW(convexHullPerimeter(loop, {0, 0, 0}), InputError);
}

}  // namespace
}  // namespace s2p
