#include "pattern/placement.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"

namespace s2p {
namespace {

double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// An arm scanned with its elbow bent 90° (upper arm down −y, forearm forward +z), straightened
// at rest (forearm down −y) by turning the forearm's bone about the elbow. A sleeve's points
// on a ring round each bone land on a ring of the same radius round the straight rest arm; with
// the shoulder's transform alone (the paper's rigid binding) the forearm's ring stays forward.
TEST(Placement, APartIsUnposedDownItsLimbBoneByBone) {
  const Eigen::Vector3d shoulder(0, 0, 0), elbow(0, -0.3, 0), wrist(0, -0.3, 0.25);
  const Eigen::Affine3d upper = Eigen::Affine3d::Identity();
  const Eigen::Affine3d fore = Eigen::Translation3d(elbow) *
                               Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()) *
                               Eigen::Translation3d(-elbow);
  ASSERT_TRUE((fore * wrist).isApprox(Eigen::Vector3d(0, -0.55, 0), 1e-12));
  const Eigen::Affine3d hand = fore;
  constexpr double kRadius = 0.05;
  constexpr int kRing = 12;
  Eigen::MatrixX3d P(2 * kRing, 3);
  for (int k = 0; k < kRing; ++k) {
    const double a = 2 * std::numbers::pi * k / kRing;
    // Round the upper arm's middle (axis y) and round the forearm's middle (axis z).
    P.row(k) = Eigen::RowVector3d(kRadius * std::cos(a), -0.15, kRadius * std::sin(a));
    P.row(kRing + k) = Eigen::RowVector3d(kRadius * std::cos(a), -0.3 + kRadius * std::sin(a), 0.12);
  }
  const Eigen::MatrixX3d rest =
      moveWithNearestBone({shoulder, elbow, wrist}, {upper, fore, hand}, P);
  const Eigen::Vector3d restWrist(0, -0.55, 0);
  for (int v = 0; v < P.rows(); ++v) {
    const Eigen::Vector3d x = rest.row(v).transpose();
    EXPECT_NEAR(distanceToSegment(x, shoulder, restWrist), kRadius, 1e-9) << "point " << v;
    EXPECT_NEAR(x.z() * x.z() + x.x() * x.x(), kRadius * kRadius, 1e-9) << "point " << v;
  }
  EXPECT_NEAR(rest(kRing, 1), -0.42, 1e-9);  // the forearm ring, 12 cm down from the elbow
  // Bound to the shoulder alone, the forearm's ring stays 12 cm in front of the rest arm.
  const Eigen::MatrixX3d rigid = moveWithNearestBone({shoulder}, {upper}, P);
  EXPECT_GT(distanceToSegment(rigid.row(kRing).transpose(), shoulder, restWrist), 0.1);

  EXPECT_THROW(moveWithNearestBone({shoulder, elbow}, {upper}, P), InputError);
}

}  // namespace
}  // namespace s2p
