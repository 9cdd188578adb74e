#include "body/posing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "body/mannequin.h"
#include "core/error.h"
#include "core/shapes.h"
#include "test_support.h"

namespace s2p {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// A small 9-joint skeleton (pelvis, spine, two 3-joint arms hanging down and forward, head)
// wrapped by an icosphere stretched over it; inverse-distance skinning weights, a joint
// regressor over each joint's nearest vertices, random shape and (optionally) pose
// directions. Enough structure for every posing formula to be exercised non-trivially.
BodyModel makeTestModel(bool correctives, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  BodyModel m;
  m.source = "test";
  m.rest = makeIcosphere(2, 1.0);
  for (int v = 0; v < m.rest.numVertices(); ++v) {
    m.rest.V(v, 0) *= 0.5;
    m.rest.V(v, 1) = 1.0 + 0.6 * m.rest.V(v, 1);
    m.rest.V(v, 2) *= 0.2;
  }
  const std::vector<Eigen::Vector3d> joints = {
      {0, 0.8, 0},      {0, 1.1, 0},       {0.15, 1.35, 0},    {0.3, 1.1, 0.05}, {0.38, 0.85, 0.1},
      {-0.15, 1.35, 0}, {-0.3, 1.1, 0.05}, {-0.38, 0.85, 0.1}, {0, 1.5, 0}};
  m.parents = {-1, 0, 1, 2, 3, 1, 5, 6, 1};
  m.jointNames = {"pelvis",     "spine",   "l_shoulder", "l_elbow", "l_wrist",
                  "r_shoulder", "r_elbow", "r_wrist",    "head"};
  const int nv = m.numVertices(), nj = 9, ns = 4;
  // Weights: inverse squared distance to the three nearest joints.
  std::vector<Eigen::Triplet<double>> tw, tr;
  for (int v = 0; v < nv; ++v) {
    std::vector<std::pair<double, int>> d;
    for (int j = 0; j < nj; ++j)
      d.push_back({(m.rest.V.row(v).transpose() - joints[j]).squaredNorm(), j});
    std::sort(d.begin(), d.end());
    double sum = 0;
    for (int k = 0; k < 3; ++k) sum += 1.0 / (d[k].first + 1e-3);
    for (int k = 0; k < 3; ++k) tw.emplace_back(v, d[k].second, 1.0 / (d[k].first + 1e-3) / sum);
  }
  m.weights.resize(nv, nj);
  m.weights.setFromTriplets(tw.begin(), tw.end());
  // Regressor: each joint is the mean of its 4 nearest template vertices.
  for (int j = 0; j < nj; ++j) {
    std::vector<std::pair<double, int>> d;
    for (int v = 0; v < nv; ++v)
      d.push_back({(m.rest.V.row(v).transpose() - joints[j]).squaredNorm(), v});
    std::sort(d.begin(), d.end());
    for (int k = 0; k < 4; ++k) tr.emplace_back(j, d[k].second, 0.25);
  }
  m.jointRegressor.resize(nj, nv);
  m.jointRegressor.setFromTriplets(tr.begin(), tr.end());
  m.shapeDirs.resize(3 * nv, ns);
  for (int i = 0; i < m.shapeDirs.size(); ++i) m.shapeDirs.data()[i] = 0.02 * U(rng);
  for (int s = 0; s < ns; ++s) m.shapeParams.push_back({"s" + std::to_string(s), "test", -5, 5});
  if (correctives) {
    m.poseDirs.resize(3 * nv, 9 * (nj - 1));
    for (int i = 0; i < m.poseDirs.size(); ++i) m.poseDirs.data()[i] = 0.01 * U(rng);
  }
  const std::array<int, 19> jointOf = {0, 1, 1, 8, 8, 1, 1, 2, 5, 3, 6, 4, 7, 0, 0, 0, 0, 0, 0};
  for (int c = 0; c < 19; ++c) m.canonical[c].joint = jointOf[c];
  for (int c = 19; c < kNumCanonical; ++c)
    m.canonical[c].vertices = {{(c * 13) % nv, 0.25}, {(c * 29 + 5) % nv, 0.75}};
  return m;
}

BodyParams randomParams(const BodyModel& m, unsigned seed, double angle = 0.6) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  BodyParams p;
  p.shape.resize(m.numShapes());
  for (int s = 0; s < m.numShapes(); ++s) p.shape(s) = 2 * U(rng);
  p.pose = BodyPose::zero(m.numJoints());
  for (int i = 0; i < p.pose.axisAngle.size(); ++i) p.pose.axisAngle.data()[i] = angle * U(rng);
  p.pose.translation = Eigen::Vector3d(U(rng), U(rng), U(rng));
  return p;
}

// params + h·e_i in the order [β | θ (joint-major) | t].
BodyParams perturb(const BodyModel& m, BodyParams p, int i, double h) {
  const int ns = m.numShapes(), nj = m.numJoints();
  if (i < ns)
    p.shape(i) += h;
  else if (i < ns + 3 * nj)
    p.pose.axisAngle((i - ns) / 3, (i - ns) % 3) += h;
  else
    p.pose.translation(i - ns - 3 * nj) += h;
  return p;
}

Eigen::VectorXd flatten(const Eigen::MatrixX3d& X) {
  Eigen::VectorXd out(3 * X.rows());
  for (int r = 0; r < X.rows(); ++r) out.segment<3>(3 * r) = X.row(r).transpose();
  return out;
}

// Central finite differences of f: params → stacked 3-vectors.
template <class F>
Eigen::MatrixXd numericJacobian(const BodyModel& m, const BodyParams& p, F f) {
  const double h = 1e-6;
  const int P = numPoseParams(m);
  Eigen::MatrixXd out;
  for (int i = 0; i < P; ++i) {
    const Eigen::VectorXd d = (f(perturb(m, p, i, h)) - f(perturb(m, p, i, -h))) / (2 * h);
    if (i == 0) out.resize(d.size(), P);
    out.col(i) = d;
  }
  return out;
}

double relativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

TEST(Posing, CanonicalNamesRoundTrip) {
  for (int c = 0; c < kNumCanonical; ++c) {
    const auto parsed = parseCanonical(toString(static_cast<Canonical>(c)));
    ASSERT_TRUE(parsed.has_value());
    EXPECT_EQ(static_cast<int>(*parsed), c);
  }
  EXPECT_STREQ(toString(Canonical::LeftWrist), "left_wrist");
  EXPECT_FALSE(parseCanonical("left_tail").has_value());
}

TEST(Posing, ValidateRejectsInconsistentModels) {
  const BodyModel good = makeTestModel(true);
  EXPECT_NO_THROW(good.validate());
  EXPECT_EQ(good.jointIndex("l_elbow"), 3);
  EXPECT_EQ(good.jointIndex("tail"), -1);
  BodyModel m = good;
  m.parents[3] = 4;  // child before parent
  EXPECT_THROW(m.validate(), InputError);
  m = good;
  RowSparse::InnerIterator(m.weights, 5).valueRef() += 0.5;
  EXPECT_THROW(m.validate(), InputError);
  m = good;
  m.canonical[static_cast<int>(Canonical::Nose)] = {};
  try {
    m.validate();
    FAIL() << "undefined canonical point accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nose"), std::string::npos) << e.what();
  }
  m = good;
  m.poseDirs.resize(3, 3);
  EXPECT_THROW(m.validate(), InputError);
}

TEST(Posing, RodriguesMatchesAngleAxisAndIsStableNearZero) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-2.0, 2.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d w(U(rng), U(rng), U(rng));
    const Eigen::Matrix3d ref = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    EXPECT_LT((axisAngleToMatrix(w) - ref).norm(), 1e-12);
    EXPECT_LT((matrixToAxisAngle(axisAngleToMatrix(w)) - w).norm(), 1e-9);
  }
  const Eigen::Vector3d tiny(1e-9, -2e-9, 3e-9);
  const Eigen::Matrix3d R = axisAngleToMatrix(tiny);
  Eigen::Matrix3d firstOrder;
  firstOrder << 1, -tiny.z(), tiny.y(), tiny.z(), 1, -tiny.x(), -tiny.y(), tiny.x(), 1;
  EXPECT_LT((R - firstOrder).norm(), 1e-16);
  EXPECT_TRUE(axisAngleToMatrix(Eigen::Vector3d::Zero()).isIdentity(0.0));
}

TEST(Posing, LeftJacobianMatchesFiniteDifferencesIncludingZero) {
  const std::vector<Eigen::Vector3d> points = {
      {0.3, -1.2, 0.7}, {1e-9, 0, -2e-9}, {0, 0, 0}, {5e-3, 2e-3, -1e-3}, {2.5, 1.0, 0.3}};
  for (const Eigen::Vector3d& w : points) {
    const Eigen::Matrix3d R = axisAngleToMatrix(w), Jl = so3LeftJacobian(w);
    for (int c = 0; c < 3; ++c) {
      const double h = 1e-6;
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(c) * h;
      const Eigen::Matrix3d fd = (axisAngleToMatrix(w + e) - axisAngleToMatrix(w - e)) / (2 * h);
      Eigen::Matrix3d K;
      const Eigen::Vector3d a = Jl.col(c);
      K << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
      EXPECT_LT(relativeError(K * R, fd), 1e-5) << "at " << w.transpose() << " c=" << c;
    }
  }
}

TEST(Posing, ZeroPoseAndShapeReproduceTemplate) {
  const BodyModel m = makeTestModel(true);
  BodyParams p;
  p.pose = BodyPose::zero(m.numJoints());
  const PosedBody b = poseBody(m, p);
  EXPECT_LT((b.mesh.V - m.rest.V).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_EQ(b.mesh.F, m.rest.F);
  const Eigen::MatrixX3d J0 = m.jointRegressor * m.rest.V;
  EXPECT_LT((b.joints - J0).cwiseAbs().maxCoeff(), 1e-14);
  for (const auto& A : b.skinning) EXPECT_TRUE(A.matrix().isIdentity(1e-14));
  // Canonical points: joints, or the weighted vertex means.
  EXPECT_LT((b.canonical.row(static_cast<int>(Canonical::LeftElbow)) - J0.row(3)).norm(), 1e-14);
  const CanonicalDef& nose = m.canonical[static_cast<int>(Canonical::Nose)];
  const Eigen::RowVector3d expect =
      0.25 * m.rest.V.row(nose.vertices[0].first) + 0.75 * m.rest.V.row(nose.vertices[1].first);
  EXPECT_LT((b.canonical.row(static_cast<int>(Canonical::Nose)) - expect).norm(), 1e-14);
}

TEST(Posing, ShapeOnlyGivesShapedTemplateAndRegressedJoints) {
  const BodyModel m = makeTestModel(true);
  BodyParams p = randomParams(m, 11);
  p.pose = BodyPose::zero(m.numJoints());
  const PosedBody b = poseBody(m, p);
  const Eigen::MatrixX3d T = shapedTemplate(m, p.shape);
  EXPECT_LT((b.mesh.V - T).cwiseAbs().maxCoeff(), 1e-13);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(T(17, k) - m.rest.V(17, k), m.shapeDirs.row(3 * 17 + k).dot(p.shape), 1e-15);
  EXPECT_LT((restJoints(m, p.shape) - m.jointRegressor * T).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((b.joints - m.jointRegressor * T).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(Posing, ShoulderQuarterTurnMovesWristUp) {
  BodyModel m = makeTestModel(false);
  // Exact joints: a regressor picking one vertex per joint would do, but simply compare with
  // the regressed rest joints and rigid rotation about the shoulder.
  BodyParams p;
  p.pose = BodyPose::zero(m.numJoints());
  p.pose.axisAngle.row(2) = Eigen::RowVector3d(0, 0, std::numbers::pi / 2);
  p.pose.translation = Eigen::Vector3d(0.1, -0.2, 0.3);
  const PosedBody b = poseBody(m, p);
  const Eigen::MatrixX3d J = restJoints(m, Eigen::VectorXd());
  const Eigen::Matrix3d Rz =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d s = J.row(2).transpose();
  for (int j : {3, 4}) {
    const Eigen::Vector3d expect = s + Rz * (J.row(j).transpose() - s) + p.pose.translation;
    EXPECT_LT((b.joints.row(j).transpose() - expect).norm(), 1e-13) << "joint " << j;
  }
  // 90° about +Z turns an arm pointing to +X (left) upwards: wrist above the shoulder now.
  EXPECT_GT(b.joints(4, 1), b.joints(2, 1));
  // Joints off the left arm do not move (apart from the translation).
  for (int j : {0, 1, 5, 6, 7, 8})
    EXPECT_LT((b.joints.row(j) - J.row(j) - p.pose.translation.transpose()).norm(), 1e-14);
}

TEST(Posing, PoseCorrectivesAreApplied) {
  const BodyModel with = makeTestModel(true);
  BodyModel without = with;
  without.poseDirs.resize(0, 0);
  BodyParams p = randomParams(with, 5);
  p.pose.axisAngle.setZero();
  p.pose.axisAngle.row(3) = Eigen::RowVector3d(0.4, 0.0, 0.0);  // left elbow only
  const PosedBody a = poseBody(with, p), b = poseBody(without, p);
  // Difference = Σ_j w_ij R^w_j · poseDirs_i·feature, feature nonzero only for the elbow.
  const Eigen::Matrix3d R = axisAngleToMatrix(Eigen::Vector3d(0.4, 0, 0));
  Eigen::VectorXd feat = Eigen::VectorXd::Zero(9 * 8);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) feat(9 * 2 + 3 * r + c) = R(r, c) - (r == c);
  for (int v = 0; v < with.numVertices(); v += 7) {
    const Eigen::Vector3d dT = with.poseDirs.middleRows(3 * v, 3) * feat;
    Eigen::Vector3d expect = Eigen::Vector3d::Zero();
    for (RowSparse::InnerIterator it(with.weights, v); it; ++it)
      expect += it.value() * (a.skinning[it.col()].linear() * dT);
    EXPECT_LT((a.mesh.V.row(v) - b.mesh.V.row(v) - expect.transpose()).norm(), 1e-14);
  }
  EXPECT_GT((a.mesh.V - b.mesh.V).norm(), 1e-4);
}

TEST(Posing, VertexJacobianMatchesFiniteDifferences) {
  for (bool correctives : {false, true}) {
    const BodyModel m = makeTestModel(correctives);
    std::vector<int> verts;
    for (int v = 0; v < m.numVertices(); v += 5) verts.push_back(v);
    for (double angle : {0.8, 0.0}) {  // a random pose and the zero pose (θ = 0 exactly)
      const BodyParams p = randomParams(m, 21, angle);
      const Eigen::MatrixXd jac = posedVertexJacobian(m, p, verts);
      const Eigen::MatrixXd fd = numericJacobian(m, p, [&](const BodyParams& q) {
        const PosedBody b = poseBody(m, q);
        Eigen::MatrixX3d X(verts.size(), 3);
        for (size_t i = 0; i < verts.size(); ++i) X.row(i) = b.mesh.V.row(verts[i]);
        return flatten(X);
      });
      ASSERT_EQ(jac.rows(), fd.rows());
      ASSERT_EQ(jac.cols(), m.numShapes() + 3 * m.numJoints() + 3);
      EXPECT_LT(relativeError(jac, fd), 1e-5)
          << "correctives " << correctives << " angle " << angle;
      // Every block is exercised: shape, pose and translation columns are all non-zero.
      EXPECT_GT(jac.leftCols(m.numShapes()).norm(), 1e-3);
      EXPECT_GT(jac.middleCols(m.numShapes() + 6, 3).norm(), 1e-3);
    }
  }
}

TEST(Posing, DenseAndSparseVertexJacobianPathsAgree) {
  const BodyModel m = makeTestModel(true);
  const BodyParams p = randomParams(m, 4);
  std::vector<int> all(m.numVertices());
  for (int v = 0; v < m.numVertices(); ++v) all[v] = v;
  const Eigen::MatrixXd dense = posedVertexJacobian(m, p, all);
  const Eigen::MatrixXd few = posedVertexJacobian(m, p, {9, 100});
  EXPECT_LT((few.middleRows(0, 3) - dense.middleRows(27, 3)).norm(), 1e-13);
  EXPECT_LT((few.middleRows(3, 3) - dense.middleRows(300, 3)).norm(), 1e-13);
}

TEST(Posing, JointAndCanonicalJacobiansMatchFiniteDifferences) {
  const BodyModel m = makeTestModel(true);
  for (double angle : {0.9, 0.0}) {
    const BodyParams p = randomParams(m, 33, angle);
    const Eigen::MatrixXd fdJ =
        numericJacobian(m, p, [&](const BodyParams& q) { return flatten(poseBody(m, q).joints); });
    EXPECT_LT(relativeError(posedJointJacobian(m, p), fdJ), 1e-5);
    const Eigen::MatrixXd fdC = numericJacobian(
        m, p, [&](const BodyParams& q) { return flatten(poseBody(m, q).canonical); });
    EXPECT_LT(relativeError(posedCanonicalJacobian(m, p), fdC), 1e-5);
  }
}

TEST(Posing, UnposeInvertsPose) {
  const BodyModel m = makeTestModel(false);
  const BodyParams p = randomParams(m, 8, 1.0);
  const PosedBody b = poseBody(m, p);
  const Eigen::MatrixX3d back = unposeSkinned(b, m.weights, b.mesh.V);
  EXPECT_LT((back - shapedTemplate(m, p.shape)).cwiseAbs().maxCoeff(), 1e-12);
  // Points rigidly carried by one joint come back exactly.
  Eigen::MatrixX3d X(3, 3);
  X << 0.1, 0.2, 0.3, -1, 0.5, 2, 0, 0, 0;
  Eigen::MatrixX3d moved(3, 3);
  for (int i = 0; i < 3; ++i) moved.row(i) = (b.skinning[4] * X.row(i).transpose()).transpose();
  EXPECT_LT((unposePoints(b, 4, moved) - X).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_THROW(unposePoints(b, 99, moved), InputError);
  EXPECT_THROW(unposeSkinned(b, m.weights, moved), InputError);
}

TEST(Posing, BadParametersThrow) {
  const BodyModel m = makeTestModel(false);
  BodyParams p = randomParams(m, 1);
  p.shape.resize(2);
  EXPECT_THROW(poseBody(m, p), InputError);
  p = randomParams(m, 1);
  p.pose.axisAngle(2, 1) = std::nan("");
  EXPECT_THROW(poseBody(m, p), InputError);
  p = randomParams(m, 1);
  p.pose.axisAngle.resize(3, 3);
  EXPECT_THROW(posedJointJacobian(m, p), InputError);
  EXPECT_THROW(posedVertexJacobian(m, randomParams(m, 1), {m.numVertices()}), InputError);
  BodyModel cyclic = m;
  cyclic.parents[2] = 7;  // a parent after its child: FK would read garbage
  EXPECT_THROW(poseBody(cyclic, randomParams(m, 1)), InputError);
  BodyModel empty;
  EXPECT_THROW(poseBody(empty, BodyParams{}), InputError);
}

double degrees(double rad) {
  return rad * 180.0 / std::numbers::pi;
}

TEST(Posing, StandardPosesPutArmsHorizontalOrAt45Degrees) {
  const BodyModel m = makeTestModel(true);
  const Eigen::VectorXd shape = Eigen::VectorXd::Constant(m.numShapes(), 1.5);
  EXPECT_TRUE(standardPose(m, shape, StandardPose::Rest).axisAngle.isZero(0.0));
  for (StandardPose which : {StandardPose::TPose, StandardPose::APose}) {
    BodyParams p;
    p.shape = shape;
    p.pose = standardPose(m, shape, which);
    const PosedBody b = poseBody(m, p);
    const double expectDown = which == StandardPose::TPose ? 0.0 : 45.0;
    for (auto [s, e, w, side] :
         {std::tuple{Canonical::LeftShoulder, Canonical::LeftElbow, Canonical::LeftWrist, 1.0},
          std::tuple{Canonical::RightShoulder, Canonical::RightElbow, Canonical::RightWrist,
                     -1.0}}) {
      const Eigen::Vector3d S = b.canonical.row(static_cast<int>(s)).transpose();
      const Eigen::Vector3d E = b.canonical.row(static_cast<int>(e)).transpose();
      const Eigen::Vector3d W = b.canonical.row(static_cast<int>(w)).transpose();
      const Eigen::Vector3d d = (W - S).normalized();
      EXPECT_NEAR(degrees(std::asin(-d.y())), expectDown, 2.0);
      EXPECT_GT(side * d.x(), 0.7);
      EXPECT_NEAR(d.z(), 0.0, 0.03);  // frontal plane
      EXPECT_LT(degrees(std::acos((E - S).normalized().dot((W - E).normalized()))), 1.0);
    }
    // Legs and head stay at rest.
    EXPECT_TRUE(p.pose.axisAngle.row(0).isZero(0.0));
    EXPECT_TRUE(p.pose.axisAngle.row(8).isZero(0.0));
  }
}

// The drape pose keeps the A-pose's 45° unless the scan held an arm higher; then that arm is
// raised to the scanned angle, never above horizontal. Each arm on its own. (The mannequin: the
// drape pose needs legs.)
TEST(Posing, DrapePoseRaisesOnlyTheArmsScannedHigherThanTheAPose) {
  const BodyModel m = makeMannequin();
  const Eigen::VectorXd shape = Eigen::VectorXd::Zero(m.numShapes());
  auto posed = [&](const BodyPose& pose) { return poseBody(m, {shape, pose}); };
  auto joint = [&](Canonical c) { return m.canonical[static_cast<int>(c)].joint; };
  // Left arm 20° below horizontal, right arm hanging 80° down.
  BodyPose scanned = armsDownPose(m, shape, 20 * std::numbers::pi / 180);
  const BodyPose hanging = armsDownPose(m, shape);
  for (Canonical c : {Canonical::RightShoulder, Canonical::RightElbow})
    scanned.axisAngle.row(joint(c)) = hanging.axisAngle.row(joint(c));
  const PosedBody fitted = posed(scanned);
  EXPECT_NEAR(degrees(armAngleBelowHorizontal(fitted, true)), 20.0, 1.0);
  EXPECT_NEAR(degrees(armAngleBelowHorizontal(fitted, false)), 80.0, 1.0);

  const DrapePoseChoice choice = drapePoseFor(m, shape, fitted);
  EXPECT_NEAR(degrees(choice.downLeft), 20.0, 1.0);
  EXPECT_DOUBLE_EQ(choice.downRight, kDrapeArmDown);
  const PosedBody drape = posed(choice.pose);
  EXPECT_NEAR(degrees(armAngleBelowHorizontal(drape, true)), 20.0, 1.0);
  EXPECT_NEAR(degrees(armAngleBelowHorizontal(drape, false)), 45.0, 1.0);

  // Arms above the shoulders: draped horizontal. A T-pose: horizontal. An A-pose: itself.
  const DrapePoseChoice raised =
      drapePoseFor(m, shape, posed(armsDownPose(m, shape, -30 * std::numbers::pi / 180)));
  EXPECT_EQ(raised.downLeft, 0.0);
  EXPECT_EQ(raised.downRight, 0.0);
  const DrapePoseChoice t =
      drapePoseFor(m, shape, posed(standardPose(m, shape, StandardPose::TPose)));
  EXPECT_NEAR(degrees(t.downLeft), 0.0, 1.0);
  EXPECT_NEAR(degrees(t.downRight), 0.0, 1.0);
  const DrapePoseChoice a =
      drapePoseFor(m, shape, posed(standardPose(m, shape, StandardPose::APose)));
  EXPECT_NEAR(degrees(a.downLeft), 45.0, 1.0);
  EXPECT_NEAR(degrees(a.downRight), 45.0, 1.0);
}

TEST(Posing, PoseJsonRoundTripAndErrors) {
  const BodyModel m = makeTestModel(false);
  test::TempDir dir;
  const BodyParams p = randomParams(m, 9);
  writePoseJson(dir / "pose.json", m, p.pose);
  const BodyPose back = readPoseJson(dir / "pose.json", m);
  EXPECT_LT((back.axisAngle - p.pose.axisAngle).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((back.translation - p.pose.translation).norm(), 1e-15);
  // Partial file, canonical names accepted.
  test::writeFile(dir / "partial.json", R"({"left_elbow": [0, 0.5, 0], "head": [0.1, 0, 0]})");
  const BodyPose partial = readPoseJson(dir / "partial.json", m);
  EXPECT_DOUBLE_EQ(partial.axisAngle(3, 1), 0.5);
  EXPECT_DOUBLE_EQ(partial.axisAngle(8, 0), 0.1);
  EXPECT_NEAR(partial.axisAngle.cwiseAbs().sum(), 0.6, 1e-15);
  EXPECT_TRUE(partial.translation.isZero(0.0));
  test::writeFile(dir / "unknown.json", R"({"left_tail": [0, 0, 0]})");
  try {
    readPoseJson(dir / "unknown.json", m);
    FAIL() << "unknown joint accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("left_tail"), std::string::npos) << e.what();
  }
  test::writeFile(dir / "short.json", R"({"head": [0, 0]})");
  EXPECT_THROW(readPoseJson(dir / "short.json", m), InputError);
  test::writeFile(dir / "garbage.json", "{\"head\": [0, ");
  EXPECT_THROW(readPoseJson(dir / "garbage.json", m), FormatError);
  EXPECT_THROW(readPoseJson(dir / "missing.json", m), IoError);
}

}  // namespace
}  // namespace s2p
