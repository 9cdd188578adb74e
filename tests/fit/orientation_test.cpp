#include "fit/orientation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/shapes.h"
#include "fit_test_bodies.h"

namespace s2p {
namespace {

using test::TestPose;

double angleDiffDeg(double a, double b) {
  double d = std::remainder(a - b, 2 * std::numbers::pi);
  return std::abs(d) * 180 / std::numbers::pi;
}

TriMesh posed(TestPose pose) {
  const BodyModel& m = test::smallMannequin();
  return poseBody(m, test::testParams(m, pose)).mesh;
}

class OrientationRotated : public ::testing::TestWithParam<std::tuple<TestPose, double>> {};

// A body facing +Z turned by α about +Y faces (sin α, 0, cos α): the yaw bringing it back is −α.
TEST_P(OrientationRotated, RecoversYawWithin10Degrees) {
  const auto [pose, degrees] = GetParam();
  const double alpha = degrees * std::numbers::pi / 180;
  const TriMesh scan = rotateAboutVertical(posed(pose), alpha);
  const Orientation o = estimateOrientation(scan);
  RecordProperty("yaw_error_deg", std::to_string(angleDiffDeg(o.yaw, -alpha)));
  RecordProperty("confidence", std::to_string(o.confidence));
  EXPECT_LT(angleDiffDeg(o.yaw, -alpha), 10.0) << "yaw " << o.yaw * 180 / std::numbers::pi;
  EXPECT_GT(o.confidence, 0.3);
  EXPECT_NEAR(o.facing.y(), 0.0, 1e-12);
  // Applying the yaw turns the facing direction to +Z.
  EXPECT_GT((yawRotation(o.yaw) * o.facing).z(), 1 - 1e-9);
  for (const auto& c : o.cues) RecordProperty(c.name, std::to_string(c.vote));
}

INSTANTIATE_TEST_SUITE_P(Mannequin, OrientationRotated,
                         ::testing::Combine(::testing::Values(TestPose::Rest, TestPose::TPose,
                                                              TestPose::Walking, TestPose::BentArm),
                                            ::testing::Values(0.0, 37.0, 90.0, 180.0, 270.0)));

TEST(Orientation, FeetPointForward) {
  const Orientation o = estimateOrientation(posed(TestPose::Rest));
  ASSERT_EQ(o.cues[0].name, "feet");
  EXPECT_GT(o.cues[0].vote, 0.01);  // the sole's centroid lies > 1 cm ahead of the ankle's
}

// A long walking stride, the back foot's heel lifted: each foot still reaches farther in front
// of its own shin than behind it, although the back foot's sole lies behind the front ankle.
TEST(Orientation, FeetPointForwardInALongStride) {
  const BodyModel& m = test::smallMannequin();
  BodyParams p = test::testParams(m, TestPose::Rest);
  p.pose.axisAngle(m.jointIndex("left_hip"), 0) = -0.5;  // left leg forward
  p.pose.axisAngle(m.jointIndex("right_hip"), 0) = 0.45;  // right leg back
  p.pose.axisAngle(m.jointIndex("right_knee"), 0) = 0.5;
  const TriMesh body = poseBody(m, p).mesh;
  for (const double degrees : {0.0, 180.0}) {
    const Orientation o = estimateOrientation(rotateAboutVertical(body, degrees * std::numbers::pi / 180));
    EXPECT_LT(angleDiffDeg(o.yaw, -degrees * std::numbers::pi / 180), 10.0) << degrees;
    EXPECT_GT(o.cues[0].vote, 0.03) << degrees;
  }
}

TEST(Orientation, RefusesPersonLyingDown) {
  TriMesh lying = posed(TestPose::Rest);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  lying.V = lying.V * R.transpose();
  try {
    estimateOrientation(lying);
    FAIL() << "a person lying down was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lying down"), std::string::npos) << e.what();
  }
}

TEST(Orientation, RefusesUpsideDown) {
  TriMesh flipped = posed(TestPose::Rest);
  flipped.V.col(1) = -flipped.V.col(1);
  flipped.V.col(0) = -flipped.V.col(0);  // a rotation by π about Z keeps the orientation
  try {
    estimateOrientation(flipped);
    FAIL() << "an upside-down person was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("upside down"), std::string::npos) << e.what();
  }
}

// A person in a long A-line dress: a cone from the hips (56 % of the height, as wide as the
// hips) down to 10 cm above the floor, its hem 1.1 m across, wider than the shoulders. Its area
// pulls the surface centroid below 45 % of the height, but the head top is far narrower than
// the feet end: not upside down.
TEST(Orientation, PersonInAnALineDressIsNotUpsideDown) {
  const TriMesh body = posed(TestPose::Rest);
  const BoundingBox box = boundingBox(body.V);
  const double H = box.extent().y(), top = box.min.y() + 0.56 * H, bottom = box.min.y() + 0.1;
  TriMesh dress = makeCylinder(40, 64, 1.0, 1.0);  // y in [0, 1]: 0 the hem, 1 the hips
  for (int v = 0; v < dress.numVertices(); ++v) {
    const double t = dress.V(v, 1), r = 0.55 + (0.19 - 0.55) * t;
    dress.V.row(v) << r * dress.V(v, 0), bottom + t * (top - bottom), r * dress.V(v, 2);
  }
  TriMesh scan = body;
  scan.V.conservativeResize(body.numVertices() + dress.numVertices(), 3);
  scan.V.bottomRows(dress.numVertices()) = dress.V;
  scan.F.conservativeResize(body.numFaces() + dress.numFaces(), 3);
  scan.F.bottomRows(dress.numFaces()) = dress.F.array() + body.numVertices();
  const double area = surfaceArea(scan);
  double centroid = 0;
  const Eigen::VectorXd a = faceAreas(scan);
  for (int f = 0; f < scan.numFaces(); ++f)
    centroid += a[f] * (scan.V(scan.F(f, 0), 1) + scan.V(scan.F(f, 1), 1) + scan.V(scan.F(f, 2), 1)) / 3;
  centroid = (centroid / area - box.min.y()) / H;
  ASSERT_LT(centroid, 0.45) << "the dress must pull the centroid below the old threshold";
  EXPECT_NO_THROW(estimateOrientation(scan));
}

// Only a torso (the body between 50 % and 80 % of its height, arms cut off at the shoulders):
// no head at either end, refused as a part of a person, not taken for a person upside down.
TEST(Orientation, RefusesOnlyATorso) {
  const TriMesh body = posed(TestPose::Rest);
  const BoundingBox box = boundingBox(body.V);
  const double H = box.extent().y(), cx = 0.5 * (box.min.x() + box.max.x());
  TriMesh torso = cutByPlane(body, Eigen::Vector3d::UnitY(), box.min.y() + 0.8 * H);
  torso = cutByPlane(torso, -Eigen::Vector3d::UnitY(), -(box.min.y() + 0.5 * H));
  torso = cutByPlane(torso, Eigen::Vector3d::UnitX(), cx + 0.19);
  torso = cutByPlane(torso, -Eigen::Vector3d::UnitX(), -(cx - 0.19));
  removeUnreferencedVertices(torso);
  ASSERT_GT(torso.numVertices(), 500);
  try {
    estimateOrientation(torso);
    FAIL() << "a torso was taken for a person";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no head at either end"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(estimateOrientation(body));
}

TEST(Orientation, RefusesSphereTinyMeshAndWrongUnits) {
  EXPECT_THROW(estimateOrientation(makeIcosphere(3, 0.8)), InputError);
  EXPECT_THROW(estimateOrientation(makeIcosphere(0, 0.9)), InputError);  // 12 vertices
  TriMesh mm = posed(TestPose::Rest);
  mm.V *= 1000.0;  // millimetres
  EXPECT_THROW(estimateOrientation(mm), InputError);
  TriMesh nan = posed(TestPose::Rest);
  nan.V(3, 1) = std::nan("");
  EXPECT_THROW(estimateOrientation(nan), InputError);
}

}  // namespace
}  // namespace s2p
