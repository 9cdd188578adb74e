#include "core/surface_point.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

TEST(SurfacePoint, PositionIsBarycentricCombination) {
  TriMesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 2, 0, 0, 0, 3, 0;
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  const SurfacePoint sp{0, {0.2, 0.3, 0.5}};
  EXPECT_TRUE(sp.position(m).isApprox(Eigen::Vector3d(0.6, 1.5, 0.0)));
  EXPECT_THROW((SurfacePoint{1, {1, 0, 0}}.position(m)), InputError);
  EXPECT_THROW((SurfacePoint{-1, {1, 0, 0}}.position(m)), InputError);
}

TEST(SurfacePoint, InterpolationOfLinearFieldIsExact) {
  const TriMesh s = makeIcosphere(2, 1.5);
  const Eigen::Vector3d g(2.0, -1.0, 3.0);
  const Eigen::VectorXd f = (s.V * g).array() + 1.0;  // f(x) = g·x + 1
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 50; ++i) {
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const SurfacePoint sp{static_cast<int>(rng() % s.numFaces()), {1 - a - b, a, b}};
    const Eigen::Vector3d p = sp.position(s);
    EXPECT_NEAR(sp.interpolate(s.F, f), g.dot(p) + 1.0, 1e-12);
    // The coordinates as a #V×3 field interpolate to the position itself.
    const Eigen::MatrixXd coords = s.V;
    EXPECT_TRUE(sp.interpolate(s.F, coords).transpose().isApprox(p, 1e-12));
  }
  const Eigen::VectorXd tooShort = Eigen::VectorXd::Zero(3);
  EXPECT_THROW((SurfacePoint{0, {1, 0, 0}}.interpolate(s.F, tooShort)), InputError);
}

TEST(SurfacePoint, AtVertexSitsOnTheVertex) {
  const TriMesh g = makeGrid(3, 3);
  const MeshTopology topo(g.F, g.numVertices());
  for (int v = 0; v < g.numVertices(); ++v) {
    const SurfacePoint a = SurfacePoint::atVertex(topo, g.F, v);
    const SurfacePoint b = SurfacePoint::atVertex(g.F, v);
    EXPECT_LT((a.position(g) - g.V.row(v).transpose()).norm(), 1e-15);
    EXPECT_LT((b.position(g) - g.V.row(v).transpose()).norm(), 1e-15);
    EXPECT_EQ(g.F(a.face, a.vertexCorner()), v);
    EXPECT_EQ(g.F(b.face, b.vertexCorner()), v);
    EXPECT_DOUBLE_EQ(a.bary.sum(), 1.0);
  }
  EXPECT_THROW(SurfacePoint::atVertex(topo, g.F, g.numVertices()), InputError);
  EXPECT_THROW(SurfacePoint::atVertex(g.F, -1), InputError);
  const MeshTopology withIsolated(g.F, g.numVertices() + 1);
  EXPECT_THROW(SurfacePoint::atVertex(withIsolated, g.F, g.numVertices()), InputError);
  EXPECT_EQ((SurfacePoint{0, {0.5, 0.5, 0}}.vertexCorner()), -1);
}

TEST(SurfacePoint, PlaneBarycentricOfLiftedPoint) {
  const Eigen::Vector3d a(1, 1, 1), b(3, 1, 1), c(1, 5, 1);
  // (0.2, 0.3, 0.5) combination lifted 4 units along the normal (+z).
  const Eigen::Vector3d inPlane = 0.2 * a + 0.3 * b + 0.5 * c;
  const Eigen::Vector3d w = planeBarycentric(inPlane + Eigen::Vector3d(0, 0, 4), a, b, c);
  EXPECT_TRUE(w.isApprox(Eigen::Vector3d(0.2, 0.3, 0.5), 1e-12));
  // Outside the triangle: one negative weight, still reconstructs the projection.
  const Eigen::Vector3d out = -0.5 * a + 1.0 * b + 0.5 * c;
  const Eigen::Vector3d wo = planeBarycentric(out - Eigen::Vector3d(0, 0, 2), a, b, c);
  EXPECT_TRUE(wo.isApprox(Eigen::Vector3d(-0.5, 1.0, 0.5), 1e-12));
}

TEST(SurfacePoint, ClosestPointMatchesBruteForce) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0.2), c(0.3, 0.8, -0.1);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 2.0);
  const int n = 200;
  for (int t = 0; t < 100; ++t) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const Eigen::Vector3d w = closestPointBarycentric(p, a, b, c);
    EXPECT_GE(w.minCoeff(), -1e-15);
    EXPECT_NEAR(w.sum(), 1.0, 1e-12);
    const double d = (w(0) * a + w(1) * b + w(2) * c - p).norm();
    double best = 1e300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Eigen::Vector3d q = a + (b - a) * i / n + (c - a) * j / n;
        best = std::min(best, (q - p).norm());
      }
    EXPECT_LE(d, best + 1e-12);
    EXPECT_GE(d, best - 0.01);  // the sampling is 1/200 of the triangle's size
  }
  // Known regions: beyond vertex c, beyond the middle of edge ab, directly above the inside.
  EXPECT_TRUE(closestPointBarycentric(c + Eigen::Vector3d(0, 5, 0), a, b, c)
                  .isApprox(Eigen::Vector3d(0, 0, 1)));
  const Eigen::Vector3d ab = 0.5 * (a + b);
  const Eigen::Vector3d outward = (b - a).cross(c - a).cross(b - a).normalized();
  EXPECT_TRUE(closestPointBarycentric(ab - 0.7 * outward, a, b, c)
                  .isApprox(Eigen::Vector3d(0.5, 0.5, 0), 1e-12));
}

TEST(SurfacePoint, DegenerateTriangleUsesItsSegment) {
  // Collinear corners: the closest point lies on the segment from a to c.
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);
  const Eigen::Vector3d w = closestPointBarycentric(Eigen::Vector3d(1.5, 1, 0), a, b, c);
  const Eigen::Vector3d q = w(0) * a + w(1) * b + w(2) * c;
  EXPECT_TRUE(q.isApprox(Eigen::Vector3d(1.5, 0, 0), 1e-12));
  EXPECT_TRUE(w.allFinite());
  const Eigen::Vector3d z = closestPointBarycentric(Eigen::Vector3d(1, 1, 1), a, a, a);
  EXPECT_TRUE(z.allFinite());
  EXPECT_NEAR(z.sum(), 1.0, 1e-15);
  EXPECT_TRUE(planeBarycentric(Eigen::Vector3d(1.5, 1, 0), a, b, c).allFinite());
}

TEST(SurfacePoint, ProjectToFaceOfGrid) {
  const TriMesh g = makeGrid(1, 1, 2.0, 2.0);  // faces (0,1,3) and (0,3,2)
  const SurfacePoint sp = projectToFace(g, 0, Eigen::Vector3d(1.5, 0.5, 3.0));
  EXPECT_TRUE(sp.position(g).isApprox(Eigen::Vector3d(1.5, 0.5, 0.0), 1e-12));
  // A point over the other face is clamped onto the shared diagonal.
  const SurfacePoint clamped = projectToFace(g, 0, Eigen::Vector3d(0.0, 2.0, 1.0));
  EXPECT_TRUE(clamped.position(g).isApprox(Eigen::Vector3d(1.0, 1.0, 0.0), 1e-12));
  EXPECT_THROW(projectToFace(g, 2, Eigen::Vector3d::Zero()), InputError);
}

}  // namespace
}  // namespace s2p
