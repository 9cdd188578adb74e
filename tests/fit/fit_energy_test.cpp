#include "fit/fit_energy.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "core/mesh_query.h"
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

// The solver's compact residuals are the full residual vector without the rows of the ignored
// and unsampled vertices (which are exactly zero there), Jacobian included.
TEST(FitEnergy, CompactResidualsAreTheNonZeroRowsOfTheFullOnes) {
  const BodyModel& m = test::smallMannequin();
  const Poser poser(m);
  const BodyParams truth = test::testParams(m, TestPose::Walking, true);
  TriMesh scan = test::offsetAlongNormals(poseBody(m, truth).mesh, 0.02);
  for (int v = 0; v < scan.numVertices(); ++v)
    if (scan.V(v, 0) < 0) scan.V(v, 0) -= 0.06;
  const ScanTarget target(scan);
  BodyParams p = test::testParams(m, TestPose::APose, false, Eigen::Vector3d(0.01, -0.02, 0.03));
  FitEnergy energy(poser, target, p, FitWeights{}, defaultJointLimits(m));
  std::vector<int> subset;  // every third vertex
  for (int v = 0; v < m.numVertices(); v += 3) subset.push_back(v);
  energy.setCorrespondences(findCorrespondences(target, poseBody(m, p).mesh, {}, &subset));
  const Correspondences& c = energy.correspondences();
  std::vector<int> active;
  for (int v = 0; v < m.numVertices(); ++v) {
    if (c.side[v] != FitSide::Ignored) active.push_back(v);
    if (v % 3 != 0) {
      EXPECT_EQ(c.side[v], FitSide::Ignored);
      EXPECT_EQ(c.face[v], -1);
    } else {
      EXPECT_GE(c.face[v], 0);
      if (c.side[v] == FitSide::Inside) {
        EXPECT_GT(c.winding[v], 0.5);
      }
      if (c.side[v] == FitSide::Outside) {
        EXPECT_LE(c.winding[v], 0.5);
      }
    }
  }
  ASSERT_GT(c.numOutside(), 50);
  ASSERT_GT(c.numInside(), 50);
  const int na = static_cast<int>(active.size()), nv = m.numVertices();
  ASSERT_EQ(energy.numCompactResiduals(), energy.numResiduals() - nv + na);

  p.pose.axisAngle(m.jointIndex("right_elbow"), 1) += 0.2;  // away from the correspondences
  for (bool shapeAndPose : {true, false}) {
    Eigen::VectorXd r, rc;
    Eigen::MatrixXd J, Jc;
    energy.evaluate(p, &r, &J, shapeAndPose);
    energy.evaluateCompact(p, &rc, &Jc, shapeAndPose);
    ASSERT_EQ(rc.size(), energy.numCompactResiduals());
    ASSERT_EQ(Jc.rows(), rc.size());
    for (int a = 0; a < na; ++a) {
      EXPECT_NEAR(rc[a], r[active[a]], 1e-12);
      EXPECT_LT((Jc.row(a) - J.row(active[a])).norm(), 1e-12);
    }
    const int priors = energy.numResiduals() - nv;
    EXPECT_EQ(rc.tail(priors), r.tail(priors));
    EXPECT_EQ(Jc.bottomRows(priors), J.bottomRows(priors));
    EXPECT_NEAR(rc.squaredNorm(), r.squaredNorm(), 1e-12 * r.squaredNorm());
  }
}

// Closest points searched from a hinted face (right, wrong, none or out of range) are the
// closest points found without hints.
TEST(FitEnergy, HintedClosestPointsEqualUnhinted) {
  const BodyModel& m = test::smallMannequin();
  const TriMesh body = poseBody(m, test::testParams(m, TestPose::Walking)).mesh;
  const MeshQuery query(body);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::uniform_int_distribution<int> face(0, body.numFaces() - 1);
  Eigen::MatrixX3d P(400, 3);
  for (int i = 0; i < P.rows(); ++i)
    P.row(i) = body.V.row(face(rng) % body.numVertices()) +
               Eigen::RowVector3d(u(rng), u(rng), u(rng)) * (i % 4 == 0 ? 1.0 : 0.1);
  const std::vector<ClosestHit> plain = query.closestPoints(P);
  std::vector<int> hints(P.rows());
  for (int i = 0; i < P.rows(); ++i)
    hints[i] = i % 4 == 0 ? -1 : i % 4 == 1 ? plain[i].face : i % 4 == 2 ? face(rng) : 1 << 30;
  const std::vector<ClosestHit> hinted = query.closestPoints(P, hints);
  for (int i = 0; i < P.rows(); ++i) {
    EXPECT_NEAR(hinted[i].distance, plain[i].distance, 1e-12) << "point " << i;
    EXPECT_LT((hinted[i].point - plain[i].point).norm(), 1e-9) << "point " << i;
  }
  EXPECT_THROW(query.closestPoints(P, std::vector<int>(3, -1)), InputError);
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
