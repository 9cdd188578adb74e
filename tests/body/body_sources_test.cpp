// The BodyModel contract, checked on every source (body_test_sources.h): the built-in mannequin,
// an SMPL-format model read through the SMPL loader, and the MPFB2 body when ../shared is
// present.
#include <gtest/gtest.h>

#include <random>

#include "body/measurements.h"
#include "body/posing.h"
#include "core/mesh_topology.h"
#include "body_test_sources.h"

namespace s2p {
namespace {


BodyParams randomParams(const BodyModel& model, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  BodyParams p{Eigen::VectorXd(model.numShapes()), BodyPose::zero(model.numJoints())};
  for (int s = 0; s < model.numShapes(); ++s) p.shape(s) = 0.5 * u(rng) * model.shapeParams[s].max;
  for (int j = 0; j < model.numJoints(); ++j)
    for (int k = 0; k < 3; ++k) p.pose.axisAngle(j, k) = 0.3 * u(rng);
  p.pose.translation = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return p;
}

TEST(BodySources, ValidClosedManifoldTemplateWithNormalisedWeights_Slow) {
  for (const auto& src : test::bodySources()) {
    SCOPED_TRACE(src.name);
    const BodyModel& m = *src.model;
    EXPECT_NO_THROW(m.validate());
    const MeshTopology topo(m.rest.F, m.numVertices());
    EXPECT_TRUE(topo.isClosed());
    EXPECT_TRUE(topo.manifoldness().isManifold());
    EXPECT_EQ(topo.numComponents(), 1);
    EXPECT_EQ(topo.eulerCharacteristic(), 2);
    const Eigen::VectorXd rowSums = m.weights * Eigen::VectorXd::Ones(m.numJoints());
    EXPECT_LT((rowSums.array() - 1.0).abs().maxCoeff(), 1e-9);
    for (int k = 0; k < m.weights.outerSize(); ++k)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(m.weights, k); it; ++it)
        EXPECT_GE(it.value(), 0.0);
    EXPECT_GE(m.numShapes(), 10);
  }
}

TEST(BodySources, ZeroPoseReproducesTheTemplateExactly_Slow) {
  for (const auto& src : test::bodySources()) {
    SCOPED_TRACE(src.name);
    const BodyModel& m = *src.model;
    const PosedBody body = poseBody(m, {Eigen::VectorXd::Zero(m.numShapes()), BodyPose::zero(m.numJoints())});
    EXPECT_LT((body.mesh.V - m.rest.V).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(body.mesh.F, m.rest.F);
  }
}

TEST(BodySources, ShoulderRotationMovesTheElbowAboutTheShoulder_Slow) {
  for (const auto& src : test::bodySources()) {
    SCOPED_TRACE(src.name);
    const BodyModel& m = *src.model;
    const int shoulder = m.canonical[static_cast<int>(Canonical::LeftShoulder)].joint;
    const int elbow = m.canonical[static_cast<int>(Canonical::LeftElbow)].joint;
    ASSERT_GE(shoulder, 0);
    ASSERT_GE(elbow, 0);
    const Eigen::VectorXd shape = Eigen::VectorXd::Zero(m.numShapes());
    const Eigen::MatrixX3d rest = restJoints(m, shape);
    BodyPose pose = BodyPose::zero(m.numJoints());
    pose.axisAngle.row(shoulder) << 0, 0, M_PI / 2;  // 90° about +Z (body frame)
    const PosedBody body = poseBody(m, {shape, pose});
    const Eigen::Vector3d s = rest.row(shoulder), e = rest.row(elbow);
    const Eigen::Vector3d expected = s + Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) * (e - s);
    EXPECT_LT((body.joints.row(elbow).transpose() - expected).norm(), 1e-9);
    // A joint outside the arm's chain does not move.
    const int rightElbow = m.canonical[static_cast<int>(Canonical::RightElbow)].joint;
    EXPECT_LT((body.joints.row(rightElbow) - rest.row(rightElbow)).norm(), 1e-12);
  }
}

TEST(BodySources, JacobiansMatchCentralDifferences_Slow) {
  for (const auto& src : test::bodySources()) {
    SCOPED_TRACE(src.name);
    const BodyModel& m = *src.model;
    const BodyParams p = randomParams(m, 7);
    std::vector<int> vertices;
    for (int i = 0; i < 12; ++i) vertices.push_back((i * 7919) % m.numVertices());
    const Eigen::MatrixXd J = posedVertexJacobian(m, p, vertices);
    const int P = numPoseParams(m);
    ASSERT_EQ(J.cols(), P);
    const double h = 1e-6;
    double worst = 0;
    for (int c = 0; c < P; ++c) {
      BodyParams plus = p, minus = p;
      auto bump = [&](BodyParams& q, double d) {
        if (c < m.numShapes()) q.shape(c) += d;
        else if (c < m.numShapes() + 3 * m.numJoints())
          q.pose.axisAngle((c - m.numShapes()) / 3, (c - m.numShapes()) % 3) += d;
        else q.pose.translation(c - m.numShapes() - 3 * m.numJoints()) += d;
      };
      bump(plus, h);
      bump(minus, -h);
      const TriMesh a = poseBody(m, plus).mesh, b = poseBody(m, minus).mesh;
      for (size_t i = 0; i < vertices.size(); ++i) {
        const Eigen::Vector3d fd = (a.V.row(vertices[i]) - b.V.row(vertices[i])).transpose() / (2 * h);
        const Eigen::Vector3d an = J.block<3, 1>(3 * i, c);
        worst = std::max(worst, (fd - an).norm() / std::max(1.0, fd.norm()));
      }
    }
    EXPECT_LT(worst, 1e-5);
  }
}

TEST(BodySources, UnposingInvertsPosing_Slow) {
  for (const auto& src : test::bodySources()) {
    SCOPED_TRACE(src.name);
    const BodyModel& m = *src.model;
    const BodyParams p = randomParams(m, 11);
    const PosedBody body = poseBody(m, p);
    const Eigen::MatrixX3d back = unposeSkinned(body, m.weights, body.mesh.V);
    EXPECT_LT((back - shapedTemplate(m, p.shape)).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(BodySources, MannequinFitsRequestedMeasurementsWithinOneCentimetre_Slow) {
  // The acceptance: request a set of tailor measurements, fit the shape, measure the
  // fitted body with the tape-measure code (measurements.h), read them back within 1 cm.
  const BodyModel& m = *test::bodySources().front().model;
  MeasurementTargets targets;
  targets.values = {{"height", 1.82}, {"chest_girth", 1.02}, {"waist_girth", 0.90},
                    {"hip_girth", 1.04}, {"thigh_girth", 0.60}, {"neck_girth", 0.40}};
  const Eigen::VectorXd shape = fitShapeToMeasurements(m, targets);
  const BodyMeasurements got = measureRestBody(m, shape);
  for (const auto& [name, value] : targets.values)
    EXPECT_NEAR(measurementField(got, name), value, 0.01) << name;
}

}  // namespace
}  // namespace s2p
