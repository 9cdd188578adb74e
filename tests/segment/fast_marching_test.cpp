#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/shapes.h"
#include "segment/geodesic.h"

namespace s2p {
namespace {

Eigen::VectorXd minus(const Eigen::VectorXd& x, double c) {
  return x - Eigen::VectorXd::Constant(x.size(), c);
}

TEST(FastMarching, StraightLineOnGridGivesDistanceToTheLine) {
  const TriMesh g = makeGrid(80, 40, 2.0, 1.0);
  const Eigen::VectorXd field = minus(g.V.col(0), 0.83);
  const Eigen::VectorXd phi =
      FastMarchingDistance(g).signedDistance(extractIsoline(g, field), field);
  // A planar front parallel to grid lines: the triangle update is exact.
  EXPECT_LT((phi - field).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(FastMarching, ObliqueLineOnGridWithinAFractionOfAnEdge) {
  // The square is convex, so the geodesic distance to the isoline (a segment ending on the
  // border) is the Euclidean distance to that segment.
  const TriMesh g = makeGrid(80, 80, 1.0, 1.0);
  const Eigen::Vector2d n = Eigen::Vector2d(1, 2).normalized();
  const double c = 0.41;
  const Eigen::VectorXd field = n.x() * g.V.col(0) + n.y() * g.V.col(1) -
                                Eigen::VectorXd::Constant(g.numVertices(), c);
  const Eigen::VectorXd phi =
      FastMarchingDistance(g).signedDistance(extractIsoline(g, field), field);
  // n·X = c meets x = 0 at y = c/n.y and y = 0 at x = c/n.x.
  const Eigen::Vector2d a(0, c / n.y()), b(c / n.x(), 0);
  double worst = 0;
  for (int v = 0; v < g.numVertices(); ++v) {
    const Eigen::Vector2d p(g.V(v, 0), g.V(v, 1));
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    worst = std::max(worst, std::abs(std::abs(phi[v]) - (a + t * (b - a) - p).norm()));
  }
  EXPECT_LT(worst, 0.5 * meanEdgeLength(g));
}

TEST(FastMarching, RingOnCylinderGivesHeightDifferenceFarAway) {
  // The heat method's far field fails here (2 m from the ring on a 4 cm mesh is fine, but
  // fast marching is exact for a front moving along the generators whatever the distance).
  const TriMesh cyl = makeCylinder(200, 48, 0.3, 4.0);
  const Eigen::VectorXd field = minus(cyl.V.col(1), 0.77);
  const Eigen::VectorXd d = FastMarchingDistance(cyl).distance(extractIsoline(cyl, field));
  EXPECT_LT((d - field.cwiseAbs()).cwiseAbs().maxCoeff(), 0.01 * 0.3);
}

TEST(FastMarching, LatitudeOnSphereMatchesArcLengthAndHasUnitGradient) {
  const TriMesh s = makeIcosphere(5);
  const double y0 = 0.2;
  const Eigen::VectorXd field = minus(s.V.col(1), y0);
  const Eigen::VectorXd phi =
      FastMarchingDistance(s).signedDistance(extractIsoline(s, field), field);
  Eigen::VectorXd exact(s.numVertices());
  for (int v = 0; v < s.numVertices(); ++v) exact[v] = std::asin(s.V(v, 1)) - std::asin(y0);
  EXPECT_LT((phi - exact).cwiseAbs().maxCoeff(), 0.01 * M_PI);
  const Eigen::VectorXd g = gradientOperator(s) * phi;
  const int nF = s.numFaces();
  double sum = 0;
  int n = 0;
  for (int f = 0; f < nF; ++f) {
    const double e = (exact[s.F(f, 0)] + exact[s.F(f, 1)] + exact[s.F(f, 2)]) / 3;
    if (std::abs(std::abs(e + std::asin(y0)) - M_PI / 2) < 0.3) continue;  // poles: cut loci
    sum += Eigen::Vector3d(g[f], g[nF + f], g[2 * nF + f]).norm();
    ++n;
  }
  ASSERT_GT(n, nF / 2);
  EXPECT_NEAR(sum / n, 1.0, 0.02);
}

TEST(FastMarching, ComponentWithoutTheCurveIsInfiniteAndEmptyCurveThrows) {
  TriMesh a = makeGrid(20, 20);
  TriMesh two;
  two.V.resize(2 * a.numVertices(), 3);
  two.V << a.V, a.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
  two.F.resize(2 * a.numFaces(), 3);
  two.F << a.F, a.F.array() + a.numVertices();
  Eigen::VectorXd field = minus(two.V.col(0), 0.55);
  field.tail(a.numVertices()).setOnes();
  const FastMarchingDistance fm(two);
  const Eigen::VectorXd d = fm.distance(extractIsoline(two, field));
  EXPECT_TRUE(std::isinf(d[a.numVertices() + 3]));
  EXPECT_NEAR(d[0], 0.55, 1e-9);
  EXPECT_THROW(fm.distance(Isoline{}), InputError);
  EXPECT_THROW(fm.signedDistance(extractIsoline(two, field), Eigen::VectorXd::Ones(3)),
               InputError);
}

}  // namespace
}  // namespace s2p
