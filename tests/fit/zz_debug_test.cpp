#include <gtest/gtest.h>
#include "fit/pose_init.h"
#include "fit_test_bodies.h"
namespace s2p {
TEST(Debug, PoseInit) {
  const BodyModel& m = test::smallMannequin();
  const BodyParams truth = test::testParams(m, test::TestPose::Rest, false, {0.1, 0.0, -0.2});
  const PosedBody target = poseBody(m, truth);
  const Extremities ex = findExtremities(target.mesh, m, {});
  std::cout << "head " << ex.headTop.transpose() << " | " << target.canonical.row(int(Canonical::HeadTop)) << "\n";
  std::cout << "lh " << ex.leftHand.transpose() << " | " << target.canonical.row(int(Canonical::LeftHandTip)) << "\n";
  std::cout << "rh " << ex.rightHand.transpose() << " | " << target.canonical.row(int(Canonical::RightHandTip)) << "\n";
  std::cout << "lf " << ex.leftFoot.transpose() << " | " << target.canonical.row(int(Canonical::LeftToeTip)) << "\n";
  std::cout << "rf " << ex.rightFoot.transpose() << " | " << target.canonical.row(int(Canonical::RightToeTip)) << "\n";
  for (auto& t : ex.targets) std::cout << toString(t.joint) << " " << t.position.transpose() << " | " << target.canonical.row(int(t.joint)) << "\n";
  const BodyParams init = initialisePose(target.mesh, m);
  const PosedBody got = poseBody(m, init);
  for (int c = 0; c < kNumCanonical; ++c) std::cout << toString(Canonical(c)) << " " << got.canonical.row(c) << " | " << target.canonical.row(c) << "\n";
}
}
