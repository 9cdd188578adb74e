#include "body/measurements.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <numbers>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kSegments = 64;

double inscribed(double r) {
  return 2 * kSegments * r * std::sin(kPi / kSegments);
}

// A part of the synthetic body: a closed mesh and the indices of its two cap centres.
struct Part {
  TriMesh mesh;
  int bottom = -1, top = -1;  // cap centre vertices (local indices)
};

// Closed cylinder of radius profile r(t), t ∈ [0, 1] along the axis from a to b, capped by
// fans around a centre vertex at each end.
Part makeTube(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
              const std::function<double(double)>& radius, int rings) {
  const double len = (b - a).norm();
  Part p;
  TriMesh m = makeCylinder(rings, kSegments, 1.0, len);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    const double r = radius(m.V(v, 1) / len);
    m.V(v, 0) *= r;
    m.V(v, 2) *= r;
  }
  const int nv = m.numVertices(), nf = m.numFaces();
  m.V.conservativeResize(nv + 2, 3);
  m.V.row(nv) << 0, 0, 0;
  m.V.row(nv + 1) << 0, len, 0;
  m.F.conservativeResize(nf + 2 * kSegments, 3);
  const int topRing = rings * kSegments;
  for (int s = 0; s < kSegments; ++s) {
    const int s1 = (s + 1) % kSegments;
    m.F.row(nf + 2 * s) << nv, s1, s;                              // bottom, facing −y
    m.F.row(nf + 2 * s + 1) << nv + 1, topRing + s, topRing + s1;  // top, facing +y
  }
  const Eigen::Matrix3d R =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), b - a).toRotationMatrix();
  m.V = ((m.V * R.transpose()).rowwise() + a.transpose()).eval();
  p.mesh = std::move(m);
  p.bottom = nv;
  p.top = nv + 1;
  return p;
}

Part makeTube(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r, int rings = 4) {
  return makeTube(
      a, b, [r](double) { return r; }, rings);
}

// The synthetic body: closed, separate parts with known radii; joints at known places.
struct SyntheticBody {
  TriMesh mesh;
  Eigen::MatrixX3d canonical = Eigen::MatrixX3d::Zero(kNumCanonical, 3);
  std::vector<std::pair<int, int>> partRange;  // [first vertex, end) per part
  std::vector<Part> parts;

  void add(Part p) {
    const int off = mesh.numVertices();
    partRange.emplace_back(off, off + p.mesh.numVertices());
    TriMesh m;
    m.V.resize(off + p.mesh.numVertices(), 3);
    m.V << mesh.V, p.mesh.V;
    m.F.resize(mesh.numFaces() + p.mesh.numFaces(), 3);
    m.F << mesh.F, (p.mesh.F.array() + off).matrix();
    mesh = std::move(m);
    p.bottom += off;
    p.top += off;
    parts.push_back(std::move(p));
  }
  void set(Canonical c, const Eigen::Vector3d& p) { canonical.row(static_cast<int>(c)) = p; }
  Eigen::Vector3d at(Canonical c) const { return canonical.row(static_cast<int>(c)); }
};

// Dimensions (metres): legs 0–0.8, torso 0.8–1.4, neck 1.4–1.5, head sphere to 1.7; arms in
// an A-pose, 30° from vertical, from the shoulder joints inside the torso.
constexpr double kLegR = 0.07, kTorsoR = 0.16, kNeckR = 0.06, kHeadR = 0.1, kArmR = 0.04;
constexpr double kArmAngle = kPi / 6, kUpperArm = 0.3, kForearm = 0.25, kHand = 0.1;
enum PartId { kLeftLeg, kRightLeg, kTorso, kNeck, kHead, kLeftArm, kRightArm };

SyntheticBody makeBody(
    const std::function<double(double)>& torsoRadius = [](double) { return kTorsoR; },
    int torsoRings = 4, double armAngle = kArmAngle) {
  using C = Canonical;
  SyntheticBody b;
  b.add(makeTube({0.1, 0, 0}, {0.1, 0.8, 0}, kLegR));
  b.add(makeTube({-0.1, 0, 0}, {-0.1, 0.8, 0}, kLegR));
  b.add(makeTube({0, 0.8, 0}, {0, 1.4, 0}, torsoRadius, torsoRings));
  b.add(makeTube({0, 1.4, 0}, {0, 1.5, 0}, kNeckR));
  Part head;
  head.mesh = makeUvSphere(24, 32, kHeadR);
  head.mesh.V.col(1).array() += 1.6;
  b.add(std::move(head));
  for (int side = 0; side < 2; ++side) {
    const double sx = side == 0 ? 1 : -1;
    const Eigen::Vector3d shoulder(0.12 * sx, 1.35, 0);
    const Eigen::Vector3d dir(sx * std::sin(armAngle), -std::cos(armAngle), 0);
    const Eigen::Vector3d elbow = shoulder + kUpperArm * dir, wrist = elbow + kForearm * dir;
    const Eigen::Vector3d tip = wrist + kHand * dir;
    b.add(makeTube(shoulder, tip, kArmR, 8));
    b.set(side == 0 ? C::LeftShoulder : C::RightShoulder, shoulder);
    b.set(side == 0 ? C::LeftElbow : C::RightElbow, elbow);
    b.set(side == 0 ? C::LeftWrist : C::RightWrist, wrist);
    b.set(side == 0 ? C::LeftHandTip : C::RightHandTip, tip);
    b.set(side == 0 ? C::LeftClavicle : C::RightClavicle, {0.05 * sx, 1.38, 0});
    b.set(side == 0 ? C::LeftHip : C::RightHip, {0.1 * sx, 0.8, 0});
    b.set(side == 0 ? C::LeftKnee : C::RightKnee, {0.1 * sx, 0.45, 0});
    b.set(side == 0 ? C::LeftAnkle : C::RightAnkle, {0.1 * sx, 0.06, 0});
    b.set(side == 0 ? C::LeftHeel : C::RightHeel, {0.1 * sx, 0, -0.05});
    b.set(side == 0 ? C::LeftToeTip : C::RightToeTip, {0.1 * sx, 0, 0.07});
  }
  b.set(C::Pelvis, {0, 0.85, 0});
  b.set(C::Spine, {0, 1.0, 0});
  b.set(C::Chest, {0, 1.2, 0});
  b.set(C::Neck, {0, 1.4, 0});
  b.set(C::Head, {0, 1.5, 0});
  b.set(C::HeadTop, {0, 1.7, 0});
  b.set(C::Nose, {0, 1.6, 0.1});
  return b;
}

// Shoulder point → elbow → wrist of the synthetic arm: the acromion is on the torso's top cap
// straight above the shoulder joint.
double expectedArmLength() {
  const Eigen::Vector3d acromion(0.12, 1.4, 0);
  const Eigen::Vector3d elbow =
      Eigen::Vector3d(0.12, 1.35, 0) +
      kUpperArm * Eigen::Vector3d(std::sin(kArmAngle), -std::cos(kArmAngle), 0);
  return (acromion - elbow).norm() + kForearm;
}

TEST(Measurements, SyntheticBodyGivesEachPartsGirthAndItsLengths) {
  const SyntheticBody body = makeBody();
  const BodyMeasurements m = measureBody(body.mesh, body.canonical);
  EXPECT_NEAR(m.height, 1.7, 1e-12);
  EXPECT_NEAR(m.inseam, 0.8, 2e-4);  // the legs part at the torso's bottom cap
  // Every girth is a plane section of one tube: the inscribed 64-gon of its radius.
  EXPECT_NEAR(m.chestGirth, inscribed(kTorsoR), 1e-9);
  EXPECT_NEAR(m.underBustGirth, inscribed(kTorsoR), 1e-9);
  EXPECT_NEAR(m.waistGirth, inscribed(kTorsoR), 1e-9);
  EXPECT_NEAR(m.hipGirth, inscribed(kTorsoR), 1e-9);
  EXPECT_NEAR(m.thighGirth, inscribed(kLegR), 1e-9);
  EXPECT_NEAR(m.upperArmGirth, inscribed(kArmR), 1e-9);
  EXPECT_NEAR(m.neckGirth, inscribed(kNeckR), 1e-9);
  EXPECT_NEAR(m.chestGirth, 2 * kPi * kTorsoR, 1e-3 * 2 * kPi * kTorsoR);
  EXPECT_NEAR(m.shoulderWidth, 0.24, 1e-12);
  EXPECT_NEAR(m.armLength, expectedArmLength(), 1e-12);
}

TEST(Measurements, ChestAndHipAreTheFullestAndWaistTheNarrowestTorsoGirth) {
  // Torso radius 0.15 ± 0.02, largest at y = 1.2 (chest) and 0.85 (hips), smallest at 1.025.
  auto r = [](double y) { return 0.15 + 0.02 * std::cos(2 * kPi * (y - 1.2) / 0.35); };
  const SyntheticBody body = makeBody([&](double t) { return r(0.8 + 0.6 * t); }, 120);
  const BodyMeasurements m = measureBody(body.mesh, body.canonical);
  EXPECT_NEAR(m.chestGirth, inscribed(0.17), 2e-4);
  EXPECT_NEAR(m.hipGirth, inscribed(0.17), 2e-4);
  EXPECT_NEAR(m.waistGirth, inscribed(0.13), 2e-4);
  // Under the bust the torso narrows toward the waist: strictly between the two.
  EXPECT_LT(m.underBustGirth, m.chestGirth - 0.01);
  EXPECT_GT(m.underBustGirth, m.waistGirth + 0.01);
}

TEST(Measurements, TPoseArmsDoNotEnterTheTorsoGirths) {
  // Arms horizontal: the planes just under them cut the arm tubes, which overlap the torso.
  const SyntheticBody body = makeBody([](double) { return kTorsoR; }, 4, kPi / 2);
  const BodyMeasurements m = measureBody(body.mesh, body.canonical);
  EXPECT_NEAR(m.height, 1.7, 1e-12);
  EXPECT_NEAR(m.inseam, 0.8, 2e-4);
  EXPECT_NEAR(m.chestGirth, inscribed(kTorsoR), 1e-9);
  EXPECT_NEAR(m.waistGirth, inscribed(kTorsoR), 1e-9);
  EXPECT_NEAR(m.hipGirth, inscribed(kTorsoR), 1e-9);
  EXPECT_NEAR(m.upperArmGirth, inscribed(kArmR), 1e-9);
  EXPECT_NEAR(m.neckGirth, inscribed(kNeckR), 1e-9);
  EXPECT_NEAR(m.thighGirth, inscribed(kLegR), 1e-9);
}

TEST(Measurements, OnlyRequestedMeasurementsAreTaken) {
  const SyntheticBody body = makeBody();
  const BodyMeasurements m = measureBody(body.mesh, body.canonical, {.only = {"waist_girth"}});
  EXPECT_NEAR(m.waistGirth, inscribed(kTorsoR), 1e-9);
  EXPECT_TRUE(std::isnan(m.height));
  EXPECT_TRUE(std::isnan(m.neckGirth));
  EXPECT_TRUE(std::isnan(m.inseam));
}

TEST(Measurements, BadInputThrowsInputError) {
  const SyntheticBody body = makeBody();
  EXPECT_THROW(measureBody(body.mesh, body.canonical.topRows(5)), InputError);
  Eigen::MatrixX3d nan = body.canonical;
  nan(3, 1) = std::nan("");
  EXPECT_THROW(measureBody(body.mesh, nan), InputError);
  EXPECT_THROW(measureBody(body.mesh, body.canonical, {.only = {"wingspan"}}), InputError);
  EXPECT_THROW(measureBody(TriMesh{}, body.canonical), InputError);
  Eigen::MatrixX3d elsewhere = body.canonical;
  elsewhere.rowwise() += Eigen::RowVector3d(0, 50, 0);  // another body's points
  EXPECT_THROW(measureBody(body.mesh, elsewhere), InputError);
  // One column for the whole body: the legs never part, so there is no crotch.
  const TriMesh column = makeTube({0, 0, 0}, {0, 1.7, 0}, 0.2).mesh;
  EXPECT_THROW(measureBody(column, body.canonical, {.only = {"inseam"}}), InputError);
  EXPECT_NEAR(measureBody(column, body.canonical, {.only = {"height"}}).height, 1.7, 1e-12);
}

TEST(Measurements, JsonRoundTripAndPartialTargets) {
  BodyMeasurements m;
  int i = 0;
  for (const auto& name : measurementNames()) measurementField(m, name) = 0.1 + 0.0731 * i++;
  const nlohmann::json j = toJson(m);
  EXPECT_EQ(j.at("units"), "m");
  EXPECT_DOUBLE_EQ(j.at("chest_girth").get<double>(), m.chestGirth);
  EXPECT_DOUBLE_EQ(j.at("cm").at("height").get<double>(), 10.0);
  const BodyMeasurements back = measurementsFromJson(nlohmann::json::parse(j.dump()));
  for (const auto& name : measurementNames())
    EXPECT_DOUBLE_EQ(measurementField(back, name), measurementField(m, name)) << name;

  const BodyMeasurements partial =
      measurementsFromJson(nlohmann::json{{"waist_girth", 0.7}, {"inseam", 0.8}});
  EXPECT_DOUBLE_EQ(partial.waistGirth, 0.7);
  EXPECT_TRUE(std::isnan(partial.chestGirth));
  const MeasurementTargets t = toTargets(partial);
  ASSERT_EQ(t.values.size(), 2u);
  EXPECT_DOUBLE_EQ(t.values.at("inseam"), 0.8);
  // NaN fields are left out of the JSON.
  EXPECT_FALSE(toJson(partial).contains("chest_girth"));

  EXPECT_THROW(measurementsFromJson(nlohmann::json::array()), InputError);
  EXPECT_THROW(measurementsFromJson(nlohmann::json{{"wasit_girth", 0.7}}), InputError);
  EXPECT_THROW(measurementsFromJson(nlohmann::json{{"waist_girth", "70cm"}}), InputError);
  EXPECT_THROW(measurementsFromJson(nlohmann::json{{"waist_girth", -0.7}}), InputError);
  EXPECT_THROW(measurementsFromJson(nlohmann::json{{"units", "cm"}, {"height", 170}}), InputError);
}

// The synthetic body as a linear BodyModel: β0 widens the torso (+1 = +1 cm of radius), β1
// the legs (+0.5 cm), β2 the arms (+0.3 cm); canonical points are means of cap centres.
BodyModel makeSyntheticModel() {
  const SyntheticBody body = makeBody();
  BodyModel model;
  model.source = "synthetic";
  model.rest = body.mesh;
  const int nv = body.mesh.numVertices();
  model.shapeDirs = Eigen::MatrixXd::Zero(3 * nv, 3);
  auto radial = [&](int part, int param, double perUnit) {
    const Part& p = body.parts[part];
    const Eigen::Vector3d a = body.mesh.V.row(p.bottom), b = body.mesh.V.row(p.top);
    const Eigen::Vector3d axis = (b - a).normalized();
    for (int v = body.partRange[part].first; v < body.partRange[part].second; ++v) {
      Eigen::Vector3d d = body.mesh.V.row(v).transpose() - a;
      d -= d.dot(axis) * axis;  // radial offset; zero on the cap centres
      if (d.norm() > 1e-9) model.shapeDirs.block<3, 1>(3 * v, param) = perUnit * d.normalized();
    }
  };
  radial(kTorso, 0, 0.01);
  radial(kLeftLeg, 1, 0.005);
  radial(kRightLeg, 1, 0.005);
  radial(kLeftArm, 2, 0.003);
  radial(kRightArm, 2, 0.003);
  model.shapeParams = {{"torso", "torso radius, +1 = +1 cm"},
                       {"legs", "leg radius, +1 = +0.5 cm"},
                       {"arms", "arm radius, +1 = +0.3 cm"}};
  model.jointRegressor.resize(1, nv);
  model.jointRegressor.insert(0, body.parts[kTorso].bottom) = 1.0;
  model.parents = {-1};
  model.jointNames = {"root"};
  model.weights.resize(nv, 1);
  for (int v = 0; v < nv; ++v) model.weights.insert(v, 0) = 1.0;
  // Each canonical point as the mix of the two cap centres of the part whose axis holds it.
  auto onAxis = [&](Canonical c, int part) {
    const Part& p = body.parts[part];
    const Eigen::Vector3d a = body.mesh.V.row(p.bottom), b = body.mesh.V.row(p.top);
    const double t = (body.at(c) - a).dot(b - a) / (b - a).squaredNorm();
    model.canonical[static_cast<int>(c)].vertices = {{p.bottom, 1 - t}, {p.top, t}};
  };
  using C = Canonical;
  for (C c : {C::Pelvis, C::Spine, C::Chest, C::LeftClavicle, C::RightClavicle}) onAxis(c, kTorso);
  for (C c : {C::Neck, C::Head, C::HeadTop, C::Nose}) onAxis(c, kNeck);
  for (C c : {C::LeftShoulder, C::LeftElbow, C::LeftWrist, C::LeftHandTip}) onAxis(c, kLeftArm);
  for (C c : {C::RightShoulder, C::RightElbow, C::RightWrist, C::RightHandTip})
    onAxis(c, kRightArm);
  for (C c : {C::LeftHip, C::LeftKnee, C::LeftAnkle, C::LeftHeel, C::LeftToeTip})
    onAxis(c, kLeftLeg);
  for (C c : {C::RightHip, C::RightKnee, C::RightAnkle, C::RightHeel, C::RightToeTip})
    onAxis(c, kRightLeg);
  return model;
}

TEST(Measurements, RestBodyOfALinearModelFollowsItsShapeParameters) {
  const BodyModel model = makeSyntheticModel();
  const BodyMeasurements m = measureRestBody(model, Eigen::Vector3d(2.0, -1.0, 1.0));
  EXPECT_NEAR(m.chestGirth, inscribed(kTorsoR + 0.02), 1e-9);
  EXPECT_NEAR(m.waistGirth, inscribed(kTorsoR + 0.02), 1e-9);
  EXPECT_NEAR(m.thighGirth, inscribed(kLegR - 0.005), 1e-9);
  EXPECT_NEAR(m.upperArmGirth, inscribed(kArmR + 0.003), 1e-9);
  EXPECT_NEAR(m.neckGirth, inscribed(kNeckR), 1e-9);
  EXPECT_NEAR(m.height, 1.7, 1e-12);
}

TEST(Measurements, FitRecoversKnownShapeParametersOfALinearModel) {
  const BodyModel model = makeSyntheticModel();
  const Eigen::Vector3d truth(2.5, -1.5, 3.0);
  MeasurementTargets targets;
  targets.values = {{"chest_girth", inscribed(kTorsoR + 0.025)},
                    {"thigh_girth", inscribed(kLegR - 0.0075)},
                    {"upper_arm_girth", inscribed(kArmR + 0.009)}};
  const Eigen::VectorXd beta = fitShapeToMeasurements(model, targets);
  ASSERT_EQ(beta.size(), 3);
  EXPECT_NEAR(beta(0), truth(0), 0.02);
  EXPECT_NEAR(beta(1), truth(1), 0.04);
  EXPECT_NEAR(beta(2), truth(2), 0.07);
  const BodyMeasurements m = measureRestBody(model, beta);
  for (const auto& [name, value] : targets.values)
    EXPECT_NEAR(measurementField(m, name), value, 1e-3) << name;  // within 1 mm of girth
}

TEST(Measurements, FitStaysInTheParameterRangeWhenATargetIsOutOfReach) {
  const BodyModel model = makeSyntheticModel();
  MeasurementTargets targets;
  targets.values = {{"hip_girth", 3.0}};  // needs a torso radius of ~0.48 m; max is 0.21
  const Eigen::VectorXd beta = fitShapeToMeasurements(model, targets);
  EXPECT_NEAR(beta(0), model.shapeParams[0].max, 1e-12);
  EXPECT_NEAR(beta(1), 0.0, 1e-6);  // parameters the target does not see stay at zero
  EXPECT_NEAR(beta(2), 0.0, 1e-6);
}

TEST(Measurements, FitRejectsBadTargetsAndModels) {
  const BodyModel model = makeSyntheticModel();
  EXPECT_THROW(fitShapeToMeasurements(model, {}), InputError);
  EXPECT_THROW(fitShapeToMeasurements(model, {{{"chest", 1.0}}}), InputError);
  EXPECT_THROW(fitShapeToMeasurements(model, {{{"chest_girth", -1.0}}}), InputError);
  EXPECT_THROW(fitShapeToMeasurements(model, {{{"chest_girth", std::nan("")}}}), InputError);
  BodyModel noShapes = model;
  noShapes.shapeDirs.resize(0, 0);
  noShapes.shapeParams.clear();
  EXPECT_THROW(fitShapeToMeasurements(noShapes, {{{"chest_girth", 1.0}}}), InputError);
  BodyModel badSizes = model;
  badSizes.shapeDirs.conservativeResize(30, 3);
  EXPECT_THROW(fitShapeToMeasurements(badSizes, {{{"chest_girth", 1.0}}}), InputError);
  EXPECT_THROW(measureRestBody(model, Eigen::VectorXd::Zero(2)), InputError);
  EXPECT_THROW(fitShapeToMeasurements(model, {{{"chest_girth", 1.0}}},
                                      {.initial = Eigen::VectorXd::Zero(2)}),
               InputError);
}

}  // namespace
}  // namespace s2p
