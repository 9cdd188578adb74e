#include "fit/pose_init.h"

#include <gtest/gtest.h>

#include "body/posing.h"
#include "core/error.h"
#include "core/shapes.h"
#include "fit_test_bodies.h"

namespace s2p {
namespace {

using test::TestPose;

class PoseInitPoses : public ::testing::TestWithParam<TestPose> {};

// The mannequin posed with known parameters: extremities found geometrically, then IK puts
// the canonical joints within 6 cm of the truth.
TEST_P(PoseInitPoses, JointsWithin60mm) {
  const BodyModel& m = test::smallMannequin();
  const BodyParams truth = test::testParams(m, GetParam(), false, {0.1, 0.0, -0.2});
  const PosedBody target = poseBody(m, truth);
  const Extremities ex = findExtremities(target.mesh, m, {});
  // Left and right are told apart: the left hand is the one near the true left hand tip.
  EXPECT_LT((ex.leftHand - target.canonical.row(int(Canonical::LeftHandTip)).transpose()).norm(),
            0.08);
  EXPECT_LT((ex.rightFoot - target.canonical.row(int(Canonical::RightToeTip)).transpose()).norm(),
            0.12);
  const BodyParams init = initialisePose(target.mesh, m);
  const PosedBody got = poseBody(m, init);
  const test::JointError e = test::canonicalJointError(got.canonical, target.canonical);
  RecordProperty("mean_joint_error_mm", std::to_string(1000 * e.mean));
  RecordProperty("max_joint_error_mm", std::to_string(1000 * e.max));
  EXPECT_LT(e.max, 0.060) << "mean " << e.mean;
}

INSTANTIATE_TEST_SUITE_P(Mannequin, PoseInitPoses,
                         ::testing::Values(TestPose::APose, TestPose::TPose, TestPose::Walking,
                                           TestPose::BentArm, TestPose::Rest));

// IK alone: targets taken from a known pose are reached (the solution reproduces them).
TEST(PoseInit, InverseKinematicsReachesReachableTargets) {
  const BodyModel& m = test::smallMannequin();
  const BodyParams truth = test::testParams(m, TestPose::TPose, false, {0.0, 0.05, 0.0});
  const PosedBody target = poseBody(m, truth);
  std::vector<JointTarget> targets;
  for (Canonical c : {Canonical::LeftWrist, Canonical::RightWrist, Canonical::LeftElbow,
                      Canonical::RightElbow, Canonical::LeftKnee, Canonical::RightKnee,
                      Canonical::LeftAnkle, Canonical::RightAnkle, Canonical::Head})
    targets.push_back({c, target.canonical.row(int(c)).transpose(), 1.0});
  BodyParams start = test::testParams(m, TestPose::Rest);
  const BodyParams got = solveInverseKinematics(m, start, targets, {.posePrior = 1e-6});
  const PosedBody body = poseBody(m, got);
  for (const auto& t : targets)
    EXPECT_LT((body.canonical.row(int(t.joint)).transpose() - t.position).norm(), 0.005)
        << toString(t.joint);
}

TEST(PoseInit, RejectsTinyMeshAndBlob) {
  const BodyModel& m = test::smallMannequin();
  EXPECT_THROW(initialisePose(makeIcosphere(0), m), InputError);
  // A sphere has no five extremities separated by 25 cm when it is small.
  EXPECT_THROW(initialisePose(makeIcosphere(3, 0.05), m), InputError);
  EXPECT_THROW(solveInverseKinematics(m, test::testParams(m, TestPose::Rest), {}), InputError);
}

}  // namespace
}  // namespace s2p
