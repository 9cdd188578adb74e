#include "synth/garment_shapes.h"

#include <gtest/gtest.h>

#include "body/body_model.h"
#include "body/posing.h"
#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// A stick figure's canonical points (metres, A-pose-like, left on +X), no mesh needed.
Eigen::MatrixX3d stickCanonical() {
  Eigen::MatrixX3d c(kNumCanonical, 3);
  auto set = [&](Canonical k, double x, double y, double z) {
    c.row(static_cast<int>(k)) << x, y, z;
  };
  set(Canonical::Pelvis, 0, 0.95, 0);
  set(Canonical::Spine, 0, 1.08, 0);
  set(Canonical::Chest, 0, 1.30, 0);
  set(Canonical::Neck, 0, 1.50, 0);
  set(Canonical::Head, 0, 1.60, 0);
  set(Canonical::HeadTop, 0, 1.75, 0);
  set(Canonical::Nose, 0, 1.62, 0.1);
  for (int s : {1, -1}) {
    const bool left = s > 0;
    set(left ? Canonical::LeftClavicle : Canonical::RightClavicle, s * 0.05, 1.42, 0);
    set(left ? Canonical::LeftShoulder : Canonical::RightShoulder, s * 0.18, 1.42, 0);
    set(left ? Canonical::LeftElbow : Canonical::RightElbow, s * 0.38, 1.22, 0);
    set(left ? Canonical::LeftWrist : Canonical::RightWrist, s * 0.56, 1.04, 0);
    set(left ? Canonical::LeftHandTip : Canonical::RightHandTip, s * 0.68, 0.92, 0);
    set(left ? Canonical::LeftHip : Canonical::RightHip, s * 0.09, 0.90, 0);
    set(left ? Canonical::LeftKnee : Canonical::RightKnee, s * 0.11, 0.50, 0);
    set(left ? Canonical::LeftAnkle : Canonical::RightAnkle, s * 0.12, 0.08, 0);
    set(left ? Canonical::LeftHeel : Canonical::RightHeel, s * 0.12, 0.0, -0.05);
    set(left ? Canonical::LeftToeTip : Canonical::RightToeTip, s * 0.12, 0.0, 0.18);
  }
  return c;
}

TEST(RestSkeleton, LocatesPointsOnTheirBones) {
  const RestSkeleton skel(stickCanonical());
  // Middle of the left upper arm, 4 cm out from the bone: upper arm at t = 0.5.
  const Eigen::Vector3d mid = 0.5 * (skel.point(Canonical::LeftShoulder) +
                                     skel.point(Canonical::LeftElbow));
  const RestSkeleton::Location a = skel.locate(mid + Eigen::Vector3d(0, 0, 0.04));
  EXPECT_EQ(a.part, BodyPart::LeftUpperArm);
  EXPECT_NEAR(a.t, 0.5, 1e-9);
  EXPECT_NEAR(a.length, std::hypot(0.2, 0.2), 1e-9);
  // The side of the torso under the arm is torso, not arm (bones carry flesh radii).
  EXPECT_EQ(skel.locate(Eigen::Vector3d(0.14, 1.15, 0)).part, BodyPart::Torso);
  EXPECT_EQ(skel.locate(Eigen::Vector3d(-0.17, 0.7, 0.05)).part, BodyPart::RightThigh);
  EXPECT_EQ(skel.locate(Eigen::Vector3d(0.12, 0.03, 0.12)).part, BodyPart::LeftFoot);
  EXPECT_EQ(skel.locate(Eigen::Vector3d(0, 1.66, 0.08)).part, BodyPart::Head);
  EXPECT_THROW(RestSkeleton(Eigen::MatrixX3d(3, 3)), InputError);
}

TEST(GarmentLayer, RegionIsSignedDistanceToTheHemCuts) {
  const RestSkeleton skel(stickCanonical());
  GarmentLayer tshirt;
  tshirt.type = GarmentType::TShirt;
  tshirt.yHem = 0.93;
  tshirt.yUpper = 1.45;
  tshirt.armT = 0.5;
  // Belly 10 cm above the hem: inside by 10 cm.
  EXPECT_NEAR(tshirt.region(skel, Eigen::Vector3d(0, 1.03, 0.12)), 0.10, 1e-9);
  // 5 cm below the hem: outside by 5 cm.
  EXPECT_NEAR(tshirt.region(skel, Eigen::Vector3d(0, 0.88, 0.12)), -0.05, 1e-9);
  // Upper arm: signed arc length to the sleeve hem at half the upper arm.
  const Eigen::Vector3d sh = skel.point(Canonical::LeftShoulder);
  const Eigen::Vector3d el = skel.point(Canonical::LeftElbow);
  const double lu = (el - sh).norm();
  const Eigen::Vector3d out(0, 0, 0.04);
  EXPECT_NEAR(tshirt.region(skel, sh + 0.3 * (el - sh) + out), 0.2 * lu, 1e-9);
  EXPECT_NEAR(tshirt.region(skel, sh + 0.7 * (el - sh) + out), -0.2 * lu, 1e-9);
  // Forearm and head are never inside a t-shirt.
  EXPECT_LT(tshirt.region(skel, 0.5 * (el + skel.point(Canonical::LeftWrist)) + out), 0);
  EXPECT_LT(tshirt.region(skel, Eigen::Vector3d(0, 1.7, 0.07)), 0);

  GarmentLayer shoes;
  shoes.type = GarmentType::Shoes;
  shoes.shoeT = 0.9;
  EXPECT_GT(shoes.region(skel, Eigen::Vector3d(0.12, 0.02, 0.1)), 0);   // foot
  EXPECT_LT(shoes.region(skel, Eigen::Vector3d(0.15, 0.30, 0.0)), 0);   // shin
}

TEST(GarmentLayer, EaseGrowsTowardsTheHemAroundItsSpec) {
  GarmentLayer L;
  L.ease = 0.01;
  L.yTop = 1.4;
  L.yBottom = 0.9;
  for (int k = 0; k < 3; ++k) L.rippleK[k] = Eigen::Vector3d(60, 0, 20 * k), L.ripplePhase[k] = k;
  double top = 0, hem = 0;
  for (int i = 0; i < 50; ++i) {
    const double x = -0.2 + 0.008 * i;
    top += L.easeAt(Eigen::Vector3d(x, 1.4, 0.1)) / 50;
    hem += L.easeAt(Eigen::Vector3d(x, 0.9, 0.1)) / 50;
  }
  EXPECT_GT(hem, 1.5 * top);
  EXPECT_NEAR(top, 0.007, 0.002);  // 0.7 × ease at the top, ripples averaging out
  EXPECT_NEAR(hem, 0.013, 0.003);  // 1.3 × ease at the hem
}

// Layers on a sphere "body" whose every vertex is torso: the union and label rules.
TEST(GarmentLayers, OuterLayerShowsAndTiesGoToTheGarment) {
  PosedBody body;
  body.mesh = makeIcosphere(2, 0.1);
  body.mesh.V.col(1).array() += 1.2;  // a ball at chest height
  body.canonical = stickCanonical();
  Outfit outfit;
  GarmentSpec inner, outer;
  inner.type = GarmentType::SleevelessTop;
  inner.ease = 0.01;
  outer.type = GarmentType::Jacket;
  outer.name = "jacket";
  outer.ease = 0.02;
  outfit.garments = {inner, outer};
  const GarmentLayers layers(body, body, outfit, 7);
  ASSERT_EQ(layers.size(), 2);
  BodySample s;
  s.rest = Eigen::Vector3d(0, 1.25, 0.1);  // front of the chest, inside both regions
  s.hasRest = true;
  s.d = 0.05;                              // far outside: the outer layer is nearest
  EXPECT_EQ(layers.visibleLayer(Eigen::Vector3d(0, 1.25, 0.15), s, nullptr), 1);
  EXPECT_EQ(layers.labelAt(Eigen::Vector3d(0, 1.25, 0.15), s), Label::Upper);
  // The union is the minimum of body and layers: the jacket, stacked over the top.
  const double u = layers.unionValue(Eigen::Vector3d(0, 1.25, 0.15), s);
  EXPECT_LT(u, s.d - 0.01);
  // Below every hem only the body remains.
  s.rest = Eigen::Vector3d(0, 0.5, 0.1);
  s.d = 0;
  EXPECT_EQ(layers.visibleLayer(Eigen::Vector3d(0, 0.5, 0.1), s, nullptr), -1);
  // The seed moves the folds.
  const GarmentLayers other(body, body, outfit, 8);
  EXPECT_NE(layers.layer(0).easeAt(s.rest), other.layer(0).easeAt(s.rest));
  Outfit bad = outfit;
  bad.garments[0].looseness = 2;
  EXPECT_THROW(GarmentLayers(body, body, bad, 7), InputError);
}

TEST(GarmentLayers, SkirtFrustumContainsTheLegsAndItsCapIsGap) {
  // Two vertical "legs" (thin cylinders) under a pelvis: the frustum must contain them.
  PosedBody body;
  TriMesh legs = makeCylinder(8, 12, 0.06, 0.85);
  const int n = legs.numVertices();
  body.mesh.V.resize(2 * n, 3);
  body.mesh.F.resize(2 * legs.numFaces(), 3);
  for (int s = 0; s < 2; ++s) {
    body.mesh.V.middleRows(s * n, n) = legs.V;
    body.mesh.V.middleRows(s * n, n).col(0).array() += s ? 0.1 : -0.1;
    body.mesh.F.middleRows(s * legs.numFaces(), legs.numFaces()) = legs.F.array() + s * n;
  }
  body.canonical = stickCanonical();
  Outfit outfit;
  GarmentSpec skirt;
  skirt.type = GarmentType::KneeSkirt;
  outfit.garments = {skirt};
  const GarmentLayers layers(body, body, outfit, 1);
  const GarmentLayer& L = layers.layer(0);
  ASSERT_TRUE(L.frustum);
  EXPECT_GT(L.fTop, L.fBottom);
  BodySample far;  // no body-following part out here
  std::vector<LayerValue> v(1);
  for (int i = 0; i < body.mesh.numVertices(); ++i) {
    const Eigen::Vector3d p = body.mesh.V.row(i).transpose();
    if (p.y() < L.fBottom + 0.01 || p.y() > L.fTop - 0.01) continue;
    layers.evaluate(p, far, v.data());
    EXPECT_LT(v[0].value, 0) << "leg point " << p.transpose() << " outside the skirt";
  }
  // Just under the middle of the hem: the cap, a gap face.
  layers.evaluate(Eigen::Vector3d(0, L.fBottom - 0.001, 0), far, v.data());
  EXPECT_TRUE(v[0].gap);
  EXPECT_NEAR(v[0].value, 0.001, 1e-9);
  layers.evaluate(Eigen::Vector3d(0, 0.5 * (L.fTop + L.fBottom), 1.0), far, v.data());
  EXPECT_FALSE(v[0].gap);
  EXPECT_GT(v[0].value, 0.5);
}

}  // namespace
}  // namespace s2p
