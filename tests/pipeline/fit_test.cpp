// The whole body fit (fitScan) on synthetic clothed scans: known answers from the true body under
// the clothes, and the same answer whichever way the scan faces.
#include <gtest/gtest.h>

#include "body/body_source.h"
#include "core/error.h"
#include "core/shapes.h"
#include "fit/scan_fit.h"
#include "synth/presets.h"
#include "synth_cases.h"

namespace s2p {
namespace {

const BodyModel& mannequin() {
  static const BodyModel m = loadBodyModel("mannequin");
  return m;
}

// The joint figures do not depend on the non-rigid step: leave it out to keep the tests quick.
ScanFitOptions rigidOnly() {
  ScanFitOptions o;
  o.nonrigid = false;
  return o;
}

struct JointErrors {
  double mean = 0, max = 0;
};

JointErrors jointErrors(const Eigen::MatrixX3d& fitted, const Eigen::MatrixX3d& truth) {
  JointErrors e;
  for (int c = 0; c < kNumCanonical; ++c) {
    const double d = (fitted.row(c) - truth.row(c)).norm();
    e.mean += d / kNumCanonical;
    e.max = std::max(e.max, d);
  }
  return e;
}

TEST(ScanFit, FindsTheBodyUnderTshirtAndTrousers_Slow) {
  const SynthCase& c = synthCase("tshirt_trousers", 12000);
  const ScanFit fit = fitScan(c.scan.scan.mesh, mannequin(), rigidOnly());
  EXPECT_EQ(fit.initialisation, "multi-start");
  EXPECT_EQ(fit.start, "geometry");  // the extremities are clear: the gate keeps them
  EXPECT_NEAR(fit.orientation.yaw, 0.0, 10 * M_PI / 180);
  const JointErrors e = jointErrors(fit.canonicalInScanFrame(), c.body.posed.canonical);
  EXPECT_LT(e.mean, 0.030);
  EXPECT_LT(e.max, 0.060);
  EXPECT_GE(fit.fit.insideOrNear, 0.95);
}

// The scan turned by 90° and by 217° about the vertical gives the same body, turned with it.
TEST(ScanFit, SameBodyWhicheverWayTheScanFaces_Slow) {
  const SynthCase& c = synthCase("tshirt_trousers", 12000);
  const Eigen::MatrixX3d reference =
      fitScan(c.scan.scan.mesh, mannequin(), rigidOnly()).canonicalInScanFrame();
  for (const double degrees : {90.0, 217.0}) {
    const Eigen::Affine3d turn = turnAboutVertical(c.scan.scan.mesh, degrees * M_PI / 180);
    TriMesh turned = c.scan.scan.mesh;
    turned.V = (turned.V * turn.linear().transpose()).rowwise() + turn.translation().transpose();
    const ScanFit fit = fitScan(turned, mannequin(), rigidOnly());
    EXPECT_NEAR(std::abs(std::remainder(fit.orientation.yaw + degrees * M_PI / 180, 2 * M_PI)), 0.0,
                10 * M_PI / 180)
        << degrees << "°";
    Eigen::MatrixX3d back = fit.canonicalInScanFrame();
    const Eigen::Affine3d undo = turn.inverse();
    back = (back * undo.linear().transpose()).rowwise() + undo.translation().transpose();
    EXPECT_LT(jointErrors(back, reference).max, 0.010) << degrees << "°";
  }
}

// Keypoints given from outside replace the geometric initialisation: the true joints, turned
// into the scan's frame, lead to the same body.
TEST(ScanFit, KeypointsFromOutsideInitialiseThePose_Slow) {
  const SynthCase& c = synthCase("tshirt_trousers", 12000);
  ScanFitOptions o = rigidOnly();
  std::vector<JointTarget> targets;
  for (const Canonical j :
       {Canonical::Pelvis, Canonical::Neck, Canonical::LeftShoulder, Canonical::RightShoulder,
        Canonical::LeftElbow, Canonical::RightElbow, Canonical::LeftWrist, Canonical::RightWrist,
        Canonical::LeftHip, Canonical::RightHip, Canonical::LeftKnee, Canonical::RightKnee,
        Canonical::LeftAnkle, Canonical::RightAnkle})
    targets.push_back({j, c.body.posed.canonical.row(static_cast<int>(j)).transpose()});
  o.keypoints = targets;
  const ScanFit fit = fitScan(c.scan.scan.mesh, mannequin(), o);
  EXPECT_EQ(fit.initialisation, "keypoints");
  const JointErrors e = jointErrors(fit.canonicalInScanFrame(), c.body.posed.canonical);
  EXPECT_LT(e.mean, 0.030);
  EXPECT_LT(e.max, 0.060);
  o.keypoints = std::vector<JointTarget>(targets.begin(), targets.begin() + 3);
  EXPECT_THROW(fitScan(c.scan.scan.mesh, mannequin(), o), InputError);
}

// Issue 17: a relaxed stance, the arms hanging 86° below horizontal with the hands against the
// thighs and the head bowed. The hands merge with the legs, so the geometric extremities fail or
// land on the wrong limb; the multi-start fit finds the arms from the arms-down start.
TEST(ScanFit, RecoversARelaxedPoseArmsAgainstTheThighs_Slow) {
  SynthOptions o = presetOptions("tshirt_trousers");
  o.pose = SynthPose::Relaxed;
  o.geometry.targetVertices = 12000;
  const SynthScan scan = synthesize(o);
  const BodyFromJson truth = bodyFromJson(scan.truth.body);
  const ScanFit fit = fitScan(scan.scan.mesh, mannequin(), rigidOnly());
  EXPECT_EQ(fit.initialisation, "multi-start");
  EXPECT_NE(fit.start, "geometry");
  const Eigen::MatrixX3d joints = fit.canonicalInScanFrame();
  for (const Canonical c :
       {Canonical::LeftWrist, Canonical::RightWrist, Canonical::LeftElbow, Canonical::RightElbow}) {
    const int i = static_cast<int>(c);
    EXPECT_LT((joints.row(i) - truth.posed.canonical.row(i)).norm(), 0.06) << toString(c);
  }
  const JointErrors e = jointErrors(joints, truth.posed.canonical);
  EXPECT_LT(e.mean, 0.030);
  EXPECT_LT(e.max, 0.080);
}

// Not a person: a sphere, a chair-like blob (a box seat on four legs with a back), a mesh of a
// handful of vertices, and a person lying down are refused before any solve.
TEST(ScanFit, RefusesWhatIsNotAStandingPerson) {
  EXPECT_THROW(fitScan(makeIcosphere(4, 0.9), mannequin(), rigidOnly()), InputError);
  TriMesh tiny = makeIcosphere(0, 0.9);
  EXPECT_THROW(fitScan(tiny, mannequin(), rigidOnly()), InputError);

  // Chair: seat 0.5×0.5 m at 0.45 m, back up to 1 m, four legs; about 1 m tall.
  std::vector<TriMesh> parts;
  auto box = [&](Eigen::Vector3d lo, Eigen::Vector3d hi) {
    TriMesh b = makeIcosphere(2, 1.0);
    for (int v = 0; v < b.numVertices(); ++v)
      for (int k = 0; k < 3; ++k)
        b.V(v, k) = lo[k] + (hi[k] - lo[k]) * (0.5 + 0.5 * std::clamp(b.V(v, k) * 1.6, -1.0, 1.0));
    parts.push_back(b);
  };
  box({-0.25, 0.40, -0.25}, {0.25, 0.47, 0.25});
  box({-0.25, 0.47, -0.25}, {0.25, 1.00, -0.20});
  for (const double x : {-0.22, 0.19})
    for (const double z : {-0.22, 0.19}) box({x, 0.0, z}, {x + 0.03, 0.40, z + 0.03});
  TriMesh chair;
  for (const TriMesh& p : parts) {
    const int base = chair.numVertices();
    chair.V.conservativeResize(base + p.numVertices(), 3);
    chair.V.bottomRows(p.numVertices()) = p.V;
    chair.F.conservativeResize(chair.numFaces() + p.numFaces(), 3);
    chair.F.bottomRows(p.numFaces()) = p.F.array() + base;
  }
  EXPECT_THROW(fitScan(chair, mannequin(), rigidOnly()), InputError);

  // The mannequin lying down: its height along +X.
  BodyParams p;
  p.pose = BodyPose::zero(mannequin().numJoints());
  TriMesh lying = poseBody(mannequin(), p).mesh;
  lying.V.col(0).swap(lying.V.col(1));
  lying.V.col(2) *= -1;  // keep the handedness (faces stay outward)
  EXPECT_THROW(fitScan(lying, mannequin(), rigidOnly()), InputError);
}

}  // namespace
}  // namespace s2p
