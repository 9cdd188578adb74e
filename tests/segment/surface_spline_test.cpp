#include "segment/surface_spline.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

Eigen::MatrixX3d ringAnchors(int n, double radius, double y, double phase = 0) {
  Eigen::MatrixX3d A(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2 * M_PI * i / n;
    A.row(i) << radius * std::cos(a), y, radius * std::sin(a);
  }
  return A;
}

TEST(SurfaceSpline, RingOfAnchorsOnCylinderGivesTheCircle) {
  const double r = 0.1, y = 0.53;
  const TriMesh cyl = makeCylinder(40, 64, r, 1.0);
  const MeshQuery q(cyl);
  const std::vector<SurfacePoint> c = surfaceSpline(q, ringAnchors(8, r, y, 0.3), true, 0.004);
  ASSERT_GT(c.size(), 150u);  // 2π·0.1 / 0.004 ≈ 157
  double maxDy = 0;
  for (const SurfacePoint& p : c) maxDy = std::max(maxDy, std::abs(p.position(cyl).y() - y));
  EXPECT_LT(maxDy, 1e-9);  // stays on the anchors' latitude (no wiggle)
}

TEST(SurfaceSpline, PassesThroughEveryAnchorAndIsSmooth) {
  // Anchors on a wavy loop: the curve must meet each anchor and turn without kinks.
  Eigen::MatrixX3d A = ringAnchors(6, 1.0, 0.0);
  for (int i = 0; i < 6; ++i) A(i, 1) = 0.1 * (i % 2);
  const Eigen::MatrixX3d P = catmullRomSamples(A, true, 0.01);
  for (int i = 0; i < 6; ++i) {
    double best = 1e9;
    for (int k = 0; k < P.rows(); ++k) best = std::min(best, (P.row(k) - A.row(i)).norm());
    EXPECT_LT(best, 1e-12) << "anchor " << i;
  }
  double maxTurn = 0;  // angle between consecutive segments
  for (int k = 0; k < P.rows(); ++k) {
    const Eigen::Vector3d a = (P.row((k + 1) % P.rows()) - P.row(k)).transpose();
    const Eigen::Vector3d b = (P.row((k + 2) % P.rows()) - P.row((k + 1) % P.rows())).transpose();
    maxTurn = std::max(maxTurn, std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)));
  }
  EXPECT_LT(maxTurn, 0.1);  // the polygon through the anchors alone turns by 60°
}

TEST(SurfaceSpline, TooFewAnchorsOrBadSpacingThrow) {
  const TriMesh cyl = makeCylinder(4, 8, 0.1, 1.0);
  const MeshQuery q(cyl);
  EXPECT_THROW(surfaceSpline(q, ringAnchors(2, 0.1, 0.5), true, 0.01), InputError);
  Eigen::MatrixX3d repeated(3, 3);
  repeated << 0.1, 0.5, 0, 0.1, 0.5, 0, 0, 0.5, 0.1;  // two distinct
  EXPECT_THROW(surfaceSpline(q, repeated, true, 0.01), InputError);
  EXPECT_NO_THROW(surfaceSpline(q, repeated, false, 0.01));
  EXPECT_THROW(surfaceSpline(q, ringAnchors(4, 0.1, 0.5), true, 0.0), InputError);
  Eigen::MatrixX3d nan = ringAnchors(4, 0.1, 0.5);
  nan(1, 1) = std::nan("");
  EXPECT_THROW(surfaceSpline(q, nan, true, 0.01), InputError);
}

}  // namespace
}  // namespace s2p
