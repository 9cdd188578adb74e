#include "pipeline/limb_straightening.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "body/mannequin.h"
#include "body/posing.h"
#include "pipeline/pipeline.h"

namespace s2p {
namespace {

const BodyModel& mannequin() {
  static const BodyModel m = makeMannequin({.targetVertices = 4000, .base = {}});
  return m;
}

// The body itself, posed with its left elbow bent by `bend`, as one "left_sleeve" panel (the
// garment frame a known rigid motion away from the parameters' frame).
struct BentCase {
  PanelsResult panels;
  PosedFeatures body;
  BodyParams straight;
};

BentCase bentCase(double bend) {
  const BodyModel& m = mannequin();
  BentCase c;
  c.body.model = std::shared_ptr<const BodyModel>(&m, [](const BodyModel*) {});
  c.body.params.shape = Eigen::VectorXd::Zero(m.numShapes());
  c.body.params.pose = BodyPose::zero(m.numJoints());
  c.straight = c.body.params;
  const int elbow = m.canonical[static_cast<int>(Canonical::LeftElbow)].joint;
  c.body.params.pose.axisAngle.row(elbow) << 0, bend, 0;
  c.body.toGarments =
      Eigen::Translation3d(0.1, -0.2, 0.3) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY());
  Panel p;
  p.name = "left_sleeve";
  p.garment = "upper";
  p.mesh = poseBody(m, c.body.params).mesh;
  p.mesh.V = (c.body.toGarments * p.mesh.V.transpose()).transpose();
  c.panels.panels.push_back(p);
  return c;
}

// A panel on an arm bent 90° comes out where the same body with a straight elbow has it; what
// the elbow does not move (no weight on it or below it) stays exactly as scanned.
TEST(LimbStraightening, ABentArmsPanelLandsOnTheStraightArm) {
  const BentCase c = bentCase(std::numbers::pi / 2);
  const std::vector<PanelReshape> r = straightenLimbs(c.panels, c.body);
  ASSERT_EQ(r.size(), 1u);
  const Panel& p = c.panels.panels[0];
  ASSERT_EQ(r[0].V.rows(), p.mesh.numVertices());
  EXPECT_NE(r[0].why.find("left elbow straightened (bent 90°)"), std::string::npos) << r[0].why;
  const PosedBody straight = poseBody(mannequin(), c.straight);
  const Eigen::MatrixX3d expected = (c.body.toGarments * straight.mesh.V.transpose()).transpose();
  EXPECT_LT((r[0].V - expected).rowwise().norm().maxCoeff(), 1e-6);
  const double moved = (r[0].V - p.mesh.V).rowwise().norm().maxCoeff();
  EXPECT_GT(moved, 0.1);  // the hand swung back by tens of centimetres
  int unchanged = 0;
  for (int v = 0; v < p.mesh.numVertices(); ++v)
    if (r[0].V.row(v) == p.mesh.V.row(v)) ++unchanged;
  EXPECT_GT(unchanged, p.mesh.numVertices() / 2);  // the trunk, the legs, the other arm
  // Its grain runs along the straight arm.
  const Eigen::Vector3d axis = c.body.toGarments.linear() *
                               (straight.canonical.row(static_cast<int>(Canonical::LeftShoulder)) -
                                straight.canonical.row(static_cast<int>(Canonical::LeftWrist)))
                                   .transpose()
                                   .normalized();
  EXPECT_GT(r[0].grain.dot(axis), 1 - 1e-9);
}

TEST(LimbStraightening, ABendUnderTheThresholdLeavesEveryPanelAsScanned) {
  const BentCase c = bentCase(10 * std::numbers::pi / 180);
  EXPECT_TRUE(straightenLimbs(c.panels, c.body).empty());
  PosedFeatures noModel = c.body;
  noModel.model.reset();
  EXPECT_TRUE(straightenLimbs(bentCase(std::numbers::pi / 2).panels, noModel).empty());
}

}  // namespace
}  // namespace s2p
