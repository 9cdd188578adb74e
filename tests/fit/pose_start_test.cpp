#include "fit/pose_start.h"

#include <gtest/gtest.h>

#include "body/posing.h"
#include "core/shapes.h"
#include "fit_test_bodies.h"

namespace s2p {
namespace {

// Two concentric spheres 0.1 m apart: each way the mean distance is the gap.
TEST(PoseStart, TwoSidedDistanceOfConcentricSpheresIsTheGap) {
  const TriMesh inner = makeIcosphere(4, 1.0), outer = makeIcosphere(4, 1.1);
  EXPECT_NEAR(twoSidedDistance(inner, outer), 0.1, 0.002);
  EXPECT_NEAR(twoSidedDistance(outer, inner), 0.1, 0.002);
  EXPECT_NEAR(twoSidedDistance(inner, inner), 0.0, 1e-9);
}

// The arms-down start hangs the arms along the sides: wrists below the elbows below the
// shoulders, the hands by the hips.
TEST(PoseStart, ArmsDownPoseHangsTheArmsAlongTheSides) {
  const BodyModel& m = test::smallMannequin();
  BodyParams p;
  p.pose = armsDownPose(m, {});
  const PosedBody b = poseBody(m, p);
  auto at = [&](Canonical c) { return Eigen::Vector3d(b.canonical.row(static_cast<int>(c))); };
  for (const bool left : {true, false}) {
    const Eigen::Vector3d s = at(left ? Canonical::LeftShoulder : Canonical::RightShoulder),
                          e = at(left ? Canonical::LeftElbow : Canonical::RightElbow),
                          w = at(left ? Canonical::LeftWrist : Canonical::RightWrist);
    EXPECT_LT(w.y(), e.y());
    EXPECT_LT(e.y(), s.y());
    EXPECT_LT(std::abs(w.x() - s.x()), 0.2 * (s - w).norm()) << left;  // 80° from horizontal
    EXPECT_GT(left ? w.x() : -w.x(), 0) << left;
  }
}

// Issue 17's known answer: the body posed with its arms against the thighs (86° below
// horizontal), used as the scan, is recovered.
TEST(PoseStart, RecoversABodyWithTheArmsAgainstTheThighs_Slow) {
  const BodyModel& m = test::smallMannequin();
  BodyParams truth;
  truth.pose = armsDownPose(m, {}, 86 * M_PI / 180);
  truth.pose.translation = {0.1, 0.0, -0.2};
  const PosedBody target = poseBody(m, truth);
  BodyFitInput input;
  input.scan = target.mesh;
  input.model = &m;
  BodyFitOptions fit;
  fit.fitShape = false;
  const GatedFitResult r = gatedFit(input, {}, fit);
  ASSERT_GE(r.scores.size(), 2u);
  double worst = 0;
  for (int c = 0; c < kNumCanonical; ++c)
    worst = std::max(worst, (r.fit.body.canonical.row(c) - target.canonical.row(c)).norm());
  EXPECT_LT(worst, 0.010) << "start " << r.start;
}

}  // namespace
}  // namespace s2p
