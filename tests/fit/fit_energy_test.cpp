#include "fit/fit_energy.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "fit_test_bodies.h"

namespace s2p {
namespace {

using test::TestPose;

// Central differences of the residual vector, one parameter at a time.
Eigen::MatrixXd finiteDifferences(const FitEnergy& e, const BodyModel& m, const BodyParams& p,
                                  double h) {
  const Eigen::VectorXd x = packParams(p);
  Eigen::MatrixXd J(e.numResiduals(), x.size());
  Eigen::VectorXd rp, rm;
  for (int k = 0; k < x.size(); ++k) {
    Eigen::VectorXd xp = x, xm = x;
    xp[k] += h;
    xm[k] -= h;
    e.evaluate(unpackParams(m, xp), &rp, nullptr);
    e.evaluate(unpackParams(m, xm), &rm, nullptr);
    J.col(k) = (rp - rm) / (2 * h);
  }
  return J;
}

// Correspondences from a scan that is the body offset outwards on one half and inwards on the
// other, so both E_out and the Geman-McClure E_in are exercised.
TEST(FitEnergy, JacobianMatchesCentralDifferences) {
  const BodyModel& m = test::smallMannequin();
  const Poser poser(m);
  const BodyParams truth = test::testParams(m, TestPose::Walking, true);
  TriMesh scan = test::offsetAlongNormals(poseBody(m, truth).mesh, 0.02);
  for (int v = 0; v < scan.numVertices(); ++v)
    if (scan.V(v, 0) < 0) scan.V(v, 0) -= 0.06;  // the right side moves away: the body pokes out
  const ScanTarget target(scan);

  BodyParams p = test::testParams(m, TestPose::APose, false, Eigen::Vector3d(0.01, -0.02, 0.03));
  p.shape.setConstant(1.5);
  p.pose.axisAngle(m.jointIndex("left_knee"), 0) = -0.5;  // beyond its limit: limit term active
  const BodyParams initial = p;
  FitEnergy energy(poser, target, initial, FitWeights{}, defaultJointLimits(m));
  energy.setCorrespondences(findCorrespondences(target, poseBody(m, p).mesh));
  ASSERT_GT(energy.correspondences().numOutside(), 100);
  ASSERT_GT(energy.correspondences().numInside(), 100);
  // Move away from the correspondences' evaluation point and from θ_init.
  p.pose.axisAngle(m.jointIndex("right_elbow"), 1) += 0.2;
  p.shape[1] += 0.7;

  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  energy.evaluate(p, &r, &J);
  const Eigen::MatrixXd Jfd = finiteDifferences(energy, m, p, 1e-6);
  ASSERT_EQ(J.rows(), Jfd.rows());
  for (int k = 0; k < J.cols(); ++k) {
    const double scale = std::max(J.col(k).norm(), 1e-8);
    EXPECT_LT((J.col(k) - Jfd.col(k)).norm() / scale, 1e-5) << "parameter " << k;
  }
  // The limit row of the knee is active and has slope √λ_lim.
  const FitEnergyTerms t = energy.terms(p);
  EXPECT_NEAR(t.limits, 10.0 * 0.3 * 0.3, 1e-9);

  // The translation-only Jacobian equals the full one in the last three columns.
  Eigen::MatrixXd Jt;
  energy.evaluate(p, &r, &Jt, false);
  EXPECT_LT((Jt.rightCols<3>() - J.rightCols<3>()).norm(), 1e-9 * J.rightCols<3>().norm());
  EXPECT_EQ(Jt.topLeftCorner(m.numVertices(), J.cols() - 3).norm(), 0.0);
}

// A body exactly inside a 2 cm offset of itself has no vertex outside: E_out = 0, while the
// inside term measures the 2 cm gap: every vertex contributes λ_in·k·GM((2 cm)²).
TEST(FitEnergy, OutsideTermVanishesInsideOffsetAndGrowsWhenMovedOut) {
  const BodyModel& m = test::smallMannequin();
  const Poser poser(m);
  const BodyParams truth = test::testParams(m, TestPose::APose, false);
  const TriMesh body = poseBody(m, truth).mesh;
  const ScanTarget target(test::offsetAlongNormals(body, 0.02));
  FitEnergy energy(poser, target, truth, FitWeights{}, defaultJointLimits(m));
  energy.setCorrespondences(findCorrespondences(target, body));
  const Correspondences& c = energy.correspondences();
  EXPECT_EQ(c.numOutside(), 0);
  EXPECT_GT(c.numInside(), 0.9 * m.numVertices());
  FitEnergyTerms t = energy.terms(truth);
  EXPECT_EQ(t.out, 0.0);
  EXPECT_EQ(t.shape, 0.0);
  EXPECT_EQ(t.pose, 0.0);
  // Distances are ≤ 2 cm (closest point of an offset surface), ≈ 2 cm on smooth parts.
  const double k = 6890.0 / m.numVertices(), s2 = 0.05 * 0.05, d2 = 0.02 * 0.02;
  EXPECT_GT(t.in, 0.5 * 0.1 * k * c.numInside() * d2 * s2 / (s2 + d2));
  EXPECT_LE(t.in, 0.1 * k * c.numInside() * 1.21 * d2 * s2 / (s2 + 1.21 * d2));

  // Moved 10 cm sideways: part of the body leaves the scan, E_out > 0.
  BodyParams moved = truth;
  moved.pose.translation.x() += 0.10;
  energy.setCorrespondences(findCorrespondences(target, poseBody(m, moved).mesh));
  t = energy.terms(moved);
  EXPECT_GT(energy.correspondences().numOutside(), 100);
  EXPECT_GT(t.out, 1e-3);
}

// Ignored vertices: opposite normals (an inverted scan) and the far-distance pruning.
TEST(FitEnergy, HeuristicsIgnoreOppositeNormalsAndFarVertices) {
  const BodyModel& m = test::smallMannequin();
  const TriMesh body = poseBody(m, test::testParams(m, TestPose::APose)).mesh;
  TriMesh inverted = test::offsetAlongNormals(body, 0.01);
  inverted.F.col(1).swap(inverted.F.col(2));
  const Correspondences c = findCorrespondences(ScanTarget(inverted), body);
  EXPECT_LT(c.numOutside() + c.numInside(), body.numVertices() / 100);

  TriMesh far = body;
  far.V.rowwise() += Eigen::RowVector3d(0, 0, 0.5);
  const Correspondences cf =
      findCorrespondences(ScanTarget(far), body, {.pruneOutside = 0.05, .pruneInside = 0.05});
  int kept = 0;
  for (int i = 0; i < body.numVertices(); ++i) {
    if (cf.side[i] == FitSide::Ignored) continue;
    ++kept;
    EXPECT_LE(cf.distance[i], 0.05);
  }
  EXPECT_LT(kept, body.numVertices() / 2);  // most of the body is more than 5 cm away
}

TEST(FitEnergy, RejectsMismatchedCorrespondences) {
  const BodyModel& m = test::smallMannequin();
  const Poser poser(m);
  const BodyParams rest = test::testParams(m, TestPose::Rest);
  const ScanTarget target(poseBody(m, rest).mesh);
  FitEnergy energy(poser, target, rest, FitWeights{}, defaultJointLimits(m));
  Correspondences c;
  c.closest = Eigen::MatrixX3d::Zero(5, 3);
  c.side.assign(5, FitSide::Outside);
  EXPECT_THROW(energy.setCorrespondences(c), InputError);
}

}  // namespace
}  // namespace s2p
