#include "segment/hem_plane.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_query.h"
#include "core/shapes.h"
#include "segment/boundary_optimizer.h"

namespace s2p {
namespace {

// A closed loop round the y axis of radius r in the plane y = h + slope·x, with the points whose
// angle lies within `bayHalfAngle` of +z lifted by `bay` (a stalled front).
Isoline tiltedLoop(double h, double slope, double r, double bayHalfAngle, double bay) {
  IsolineCurve c;
  for (int i = 0; i < 120; ++i) {
    const double a = 2 * M_PI * i / 120;
    IsolinePoint p;
    const double x = r * std::sin(a), z = r * std::cos(a);
    const double lift = std::abs(std::remainder(a, 2 * M_PI)) < bayHalfAngle ? bay : 0.0;
    p.position = {x, h + slope * x + lift, z};
    c.points.push_back(p);
  }
  Isoline iso;
  iso.curves.push_back(c);
  return iso;
}

TEST(HemPlane, TheTrimmedPlaneIgnoresABayOfAQuarterOfTheCurve) {
  // A waist loop tilted 0.2 (11°) with a 9 cm bay over 60° of its round: the plain fit tilts
  // toward the bay, the trimmed one recovers the loop's plane.
  const Isoline loop = tiltedLoop(1.0, 0.2, 0.15, M_PI / 6, 0.09);
  const auto plane = trimmedCurvePlane(loop);
  ASSERT_TRUE(plane.has_value());
  const Eigen::Vector3d truth = Eigen::Vector3d(-0.2, 1, 0).normalized();
  EXPECT_GT(std::abs(plane->normal().dot(truth)), std::cos(M_PI / 180));
  // The plane passes through the loop's centre at the axis: y = 1.0 at x = z = 0.
  const Eigen::Vector3d onAxis(0, 1.0, 0);
  EXPECT_LT(std::abs((onAxis - plane->centre).dot(plane->normal())), 0.002);

  // Untrimmed, the bay pulls the plane up by several millimetres: what the trimming is for.
  const auto plain = trimmedCurvePlane(loop, 0.0);
  ASSERT_TRUE(plain.has_value());
  EXPECT_GT(std::abs((onAxis - plain->centre).dot(plain->normal())), 0.01);
}

TEST(HemPlane, TooFewPointsGiveNoPlaneAndBadArgumentsThrow) {
  Isoline few;
  few.curves.emplace_back();
  for (int i = 0; i < 7; ++i) {
    IsolinePoint p;
    p.position = {std::cos(i), 0, std::sin(i)};
    few.curves[0].points.push_back(p);
  }
  EXPECT_FALSE(trimmedCurvePlane(few).has_value());
  EXPECT_THROW(trimmedCurvePlane(few, 1.0), InputError);
  const TriMesh m = makeCylinder(10, 12, 0.1, 1.0);
  FittedPlane p;
  EXPECT_THROW(planeDisplacement(m, p, {0, 1, 0}, 0.0), InputError);
  EXPECT_THROW(planeDisplacement(m, p, {0, 1, 0}, std::nan("")), InputError);
}

TEST(HemPlane, DisplacementIsPositiveOnTheGivenSideAndLinearInTheBand) {
  const TriMesh m = makeCylinder(101, 24, 0.1, 1.0);
  FittedPlane p;
  p.centre = {0, 0.5, 0};
  p.axes.col(0) = Eigen::Vector3d(0, -1, 0);  // the normal points down; the side is given apart
  const Eigen::VectorXd d = planeDisplacement(m, p, {0, 0.9, 0}, 0.02);
  for (int v = 0; v < m.numVertices(); ++v) {
    const double y = m.V(v, 1);
    EXPECT_NEAR(d[v], std::clamp((y - 0.5) / 0.02, -1.0, 1.0), 1e-9) << "y = " << y;
  }
}

// The cylinder of radius 0.1 and height 1: the positive garment's colour above y = 0.4, the
// negative's below; in a 60° sector from y = 0.3 to 0.7 a colour both hold (φ_d = 0). From a
// start ring at 0.55 the front reaches 0.4 everywhere but the sector, where only the length
// regulariser moves it: a bay. The second pass with the plane's push on the neutral vertices
// fills it.
TEST(HemPlane, ThePlanePassFillsABayTheColourCannotReach) {
  constexpr double kR = 0.15;
  const TriMesh m = makeCylinder(201, 96, kR, 1.0);
  const MeshQuery q(m);
  auto closest = [&q](const Eigen::Vector3d& p) {
    const ClosestHit h = q.closestPoint(p);
    return SurfacePoint{h.face, h.bary};
  };
  std::vector<SurfacePoint> start;
  std::vector<ValueConstraint> signs;
  for (int i = 0; i < 12; ++i) {
    const double a = 2 * M_PI * (i + 0.25) / 12;
    start.push_back(closest({kR * std::sin(a), 0.5, kR * std::cos(a)}));
  }
  for (int i = 0; i < 4; ++i) {
    const double a = M_PI / 2 * i;
    signs.push_back({closest({kR * std::sin(a), 0.95, kR * std::cos(a)}), 1.0});
    signs.push_back({closest({kR * std::sin(a), 0.05, kR * std::cos(a)}), -1.0});
  }
  Eigen::VectorXd phiD(m.numVertices());
  std::vector<bool> neutral(static_cast<size_t>(m.numVertices()), false);
  for (int v = 0; v < m.numVertices(); ++v) {
    const double y = m.V(v, 1), angle = std::atan2(m.V(v, 0), m.V(v, 2));
    neutral[static_cast<size_t>(v)] = std::abs(angle) < M_PI / 6 && y > 0.3 && y < 0.55;
    phiD[v] = neutral[static_cast<size_t>(v)] ? 0.0 : (y >= 0.4 ? 1.0 : -1.0);
  }
  BoundaryOptimizer optimizer(m);
  const BoundaryResult first = optimizer.run({start}, signs, phiD);
  ASSERT_FALSE(first.vanished);
  auto highest = [](const Isoline& iso) {
    double top = -1;
    for (const IsolineCurve& c : iso.curves)
      for (const IsolinePoint& p : c.points) top = std::max(top, p.position.y());
    return top;
  };
  // Colour alone leaves the bay: the front stalls well above the edge in the sector.
  EXPECT_GT(highest(first.boundary), 0.43);

  const auto plane = trimmedCurvePlane(first.boundary);
  ASSERT_TRUE(plane.has_value());
  const Eigen::VectorXd toPlane = planeDisplacement(m, *plane, {0, 0.9, 0});
  Eigen::VectorXd phiPlane = phiD;
  const Eigen::VectorXd area = vertexAreas(m);
  double neutralArea = 0;
  for (int v = 0; v < m.numVertices(); ++v) {
    if (!neutral[static_cast<size_t>(v)]) continue;
    phiPlane[v] = toPlane[v];
    neutralArea += area[v];
  }
  // Its change measured over the part that can move, as the segmenter does.
  const double tolerance = BoundaryOptions{}.tolerance * neutralArea / area.sum();
  const BoundaryResult second = optimizer.iterate(first.phi, signs, phiPlane, tolerance);
  ASSERT_FALSE(second.vanished);
  ASSERT_EQ(second.boundary.curves.size(), 1u);
  for (const IsolinePoint& p : second.boundary.curves[0].points)
    EXPECT_NEAR(p.position.y(), 0.4, 0.005);
}

}  // namespace
}  // namespace s2p
