#include "segment/geodesic.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/shapes.h"

namespace s2p {
namespace {

Eigen::VectorXd minus(const Eigen::VectorXd& x, double c) {
  return x - Eigen::VectorXd::Constant(x.size(), c);
}

TEST(HeatDistance, StraightLineOnGridGivesDistanceToTheLine) {
  const TriMesh g = makeGrid(80, 40, 2.0, 1.0);
  const Eigen::VectorXd field = minus(g.V.col(0), 0.83);
  const HeatDistance heat(g);
  const Eigen::VectorXd phi = heat.signedDistance(extractIsoline(g, field), field);
  const double err = (phi - field).cwiseAbs().maxCoeff();
  EXPECT_LT(err, 0.02 * 2.0);
  for (int v = 0; v < g.numVertices(); ++v)
    if (std::abs(field[v]) > 1e-3) {
      EXPECT_EQ(phi[v] > 0, field[v] > 0) << v;
    }  // sign follows
}

TEST(HeatDistance, RingOnCylinderGivesHeightDifference) {
  const TriMesh cyl = makeCylinder(60, 48, 0.3, 2.0);
  const Eigen::VectorXd field = minus(cyl.V.col(1), 0.77);
  const HeatDistance heat(cyl);
  const Eigen::VectorXd d = heat.distance(extractIsoline(cyl, field));
  EXPECT_LT((d - field.cwiseAbs()).cwiseAbs().maxCoeff(), 0.02 * 2.0);
  EXPECT_GE(d.minCoeff(), 0.0);
}

TEST(HeatDistance, LatitudeOnSphereMatchesArcLengthAndHasUnitGradient) {
  const TriMesh s = makeIcosphere(5);
  const double y0 = 0.2;
  const Eigen::VectorXd field = minus(s.V.col(1), y0);
  const HeatDistance heat(s);
  const Eigen::VectorXd phi = heat.signedDistance(extractIsoline(s, field), field);
  // Exact: difference of latitudes (radius 1).
  Eigen::VectorXd exact(s.numVertices());
  for (int v = 0; v < s.numVertices(); ++v) exact[v] = std::asin(s.V(v, 1)) - std::asin(y0);
  EXPECT_LT((phi - exact).cwiseAbs().maxCoeff(), 0.02 * M_PI);

  // |∇φ| ≈ 1 away from the curve and from the cut loci (the poles).
  const Eigen::VectorXd g = gradientOperator(s) * phi;
  const int nF = s.numFaces();
  const double h = meanEdgeLength(s);
  double sum = 0;
  int n = 0;
  for (int f = 0; f < nF; ++f) {
    const double e = (exact[s.F(f, 0)] + exact[s.F(f, 1)] + exact[s.F(f, 2)]) / 3;
    const double lat = e + std::asin(y0);
    if (std::abs(e) < 3 * h || std::abs(std::abs(lat) - M_PI / 2) < 0.3) continue;
    sum += Eigen::Vector3d(g[f], g[nF + f], g[2 * nF + f]).norm();
    ++n;
  }
  ASSERT_GT(n, nF / 2);
  EXPECT_NEAR(sum / n, 1.0, 0.05);
}

TEST(HeatDistance, ComponentWithoutTheCurveIsInfinite) {
  TriMesh a = makeGrid(40, 40);
  TriMesh two;
  two.V.resize(2 * a.numVertices(), 3);
  two.V << a.V, a.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
  two.F.resize(2 * a.numFaces(), 3);
  two.F << a.F, a.F.array() + a.numVertices();
  Eigen::VectorXd field = minus(two.V.col(0), 0.55);
  field.tail(a.numVertices()).setOnes();
  const HeatDistance heat(two);
  const Eigen::VectorXd d = heat.distance(extractIsoline(two, field));
  EXPECT_TRUE(std::isinf(d[a.numVertices() + 3]));
  EXPECT_NEAR(d[20 * 41], 0.55, 0.02);  // vertex (0, 0.5)
}

TEST(HeatDistance, EmptyCurveOrWrongSignSizeThrows) {
  const TriMesh s = makeIcosphere(2);
  const HeatDistance heat(s);
  EXPECT_THROW(heat.distance(Isoline{}), InputError);
  const Eigen::VectorXd field = s.V.col(1);
  EXPECT_THROW(heat.signedDistance(extractIsoline(s, field), Eigen::VectorXd::Ones(3)), InputError);
}

TEST(HeatDistance, OneShotEqualsTheSolverObject) {
  const TriMesh s = makeIcosphere(3);
  const Eigen::VectorXd field = minus(s.V.col(2), -0.1);
  const Eigen::VectorXd a = signedDistanceFromZeroSet(s, field);
  const Eigen::VectorXd b = HeatDistance(s).signedDistance(extractIsoline(s, field), field);
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace s2p
