#include "fit_test_bodies.h"

#include "body/mannequin.h"

namespace s2p::test {

const BodyModel& smallMannequin() {
  static const BodyModel model = makeMannequin({.targetVertices = 4000, .base = {}});
  return model;
}

BodyParams testParams(const BodyModel& model, TestPose pose, bool shaped,
                      const Eigen::Vector3d& translation) {
  BodyParams p;
  p.shape = Eigen::VectorXd::Zero(model.numShapes());
  if (shaped && model.numShapes() >= 4) {
    p.shape[0] = 4.0;   // +4 cm taller
    p.shape[1] = 6.0;   // chest +6 cm
    p.shape[2] = -3.0;  // waist −3 cm
    p.shape[3] = 2.0;   // hips +2 cm
  }
  auto set = [&](const char* joint, double x, double y, double z) {
    const int j = model.jointIndex(joint);
    if (j >= 0) p.pose.axisAngle.row(j) = Eigen::RowVector3d(x, y, z);
  };
  switch (pose) {
    case TestPose::Rest:
      p.pose = BodyPose::zero(model.numJoints());
      break;
    case TestPose::APose:
      p.pose = standardPose(model, p.shape, StandardPose::APose);
      break;
    case TestPose::TPose:
      p.pose = standardPose(model, p.shape, StandardPose::TPose);
      break;
    case TestPose::Walking:
      p.pose = BodyPose::zero(model.numJoints());
      set("left_hip", -0.45, 0, 0);
      set("right_hip", 0.3, 0, 0);
      set("left_knee", 0.15, 0, 0);
      set("right_knee", 0.6, 0, 0);
      set("left_shoulder", 0.35, 0, 0);
      set("right_shoulder", -0.35, 0, 0);
      set("left_elbow", -0.3, 0, 0);
      set("right_elbow", -0.3, 0, 0);
      break;
    case TestPose::BentArm:
      p.pose = BodyPose::zero(model.numJoints());
      set("left_elbow", -1.3, 0, 0);
      set("right_shoulder", 0, 0, -0.3);
      break;
  }
  p.pose.translation = translation;
  return p;
}

TriMesh offsetAlongNormals(const TriMesh& mesh, double distance) {
  TriMesh out = mesh;
  out.V += distance * vertexNormals(mesh);
  return out;
}

JointError canonicalJointError(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b,
                               bool jointsOnly) {
  JointError e;
  int n = 0;
  for (int c = 0; c < a.rows(); ++c) {
    if (jointsOnly && c >= static_cast<int>(Canonical::LeftHandTip)) continue;
    const double d = (a.row(c) - b.row(c)).norm();
    e.mean += d;
    e.max = std::max(e.max, d);
    ++n;
  }
  e.mean /= std::max(n, 1);
  return e;
}

}  // namespace s2p::test
