// The armhole seam where a lowered arm touches the torso (§6.1.2 and beyond): a body of two
// capsules, a trunk and a left arm hanging 12° from it whose inner side presses against the
// trunk's side over its top 12 cm, and a t-shirt 15 mm over it, so that the shirt's sleeve and
// side are one surface from the armpit down to near the cuff. The paper's constraints (anchors,
// −1 on the cuff, +1 on the neckline and hem, + on the chest) leave the trunk's side under the
// arm to the biharmonic's extrapolation between a cuff beside it and + points far away. Known
// answer: the shirt over the trunk stays trunk (φ > 0); with sleeve points, the shirt over the
// arm stays sleeve (φ < 0).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "body/level_set_mesh.h"
#include "core/mesh_query.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"
#include "pattern/body_frame.h"
#include "pattern/seam_lines.h"

namespace s2p {
namespace {

using Vec3 = Eigen::Vector3d;

double capsule(const Vec3& p, const Vec3& a, const Vec3& b, double r) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm() - r;
}

double smoothMin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}

struct ArmDownScene {
  const double angle = 12 * M_PI / 180;
  const Vec3 shoulder{0.165, 0.42, 0};
  const Vec3 down{std::sin(angle), -std::cos(angle), 0};  // along the left arm
  double trunk(const Vec3& p) const { return capsule(p, {0, -0.15, 0}, {0, 0.42, 0}, 0.14); }
  double arm(const Vec3& p) const { return capsule(p, shoulder, shoulder + 0.45 * down, 0.05); }
  double body(const Vec3& p) const { return smoothMin(trunk(p), arm(p), 0.02); }
  double along(const Vec3& p) const { return (p - shoulder).dot(down); }  // m down the arm

  // The zero set of f (negative inside) on a grid of `voxel`, outward oriented.
  static TriMesh mesh(const std::function<double(const Vec3&)>& f, double voxel) {
    return meshImplicit(f, Vec3(-0.25, -0.25, -0.22), Vec3(0.8, 0.9, 0.44), voxel);
  }

  // The body and a shirt 15 mm over it: neckline at y = 0.5, hem at y = −0.1, cuff 25 cm down
  // the arm.
  TriMesh bodyMesh = mesh([this](const Vec3& p) { return body(p); }, 0.008);
  TriMesh shirt = [this] {
    const TriMesh closed = mesh([this](const Vec3& p) { return body(p) - 0.015; }, 0.008);
    std::vector<int> keep;
    for (int f = 0; f < closed.numFaces(); ++f) {
      const Vec3 c = (closed.V.row(closed.F(f, 0)) + closed.V.row(closed.F(f, 1)) +
                      closed.V.row(closed.F(f, 2)))
                         .transpose() /
                     3;
      const bool cuff = along(c) > 0.25 && arm(c) < trunk(c);
      if (c.y() < 0.5 && c.y() > -0.1 && !cuff) keep.push_back(f);
    }
    TriMesh m;
    m.V = closed.V;
    m.F.resize(static_cast<int>(keep.size()), 3);
    for (size_t i = 0; i < keep.size(); ++i) m.F.row(static_cast<int>(i)) = closed.F.row(keep[i]);
    removeUnreferencedVertices(m);
    return m;
  }();

  // Skinning by construction: arm where the arm's capsule is nearer by 1 cm, trunk where the
  // trunk's is, blended in between.
  Eigen::MatrixXd limbWeight() const {
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(bodyMesh.numVertices(), 6);
    for (int v = 0; v < bodyMesh.numVertices(); ++v) {
      const Vec3 p = bodyMesh.V.row(v).transpose();
      const double a = std::clamp(0.5 + (trunk(p) - arm(p)) / 0.02, 0.0, 1.0);
      W(v, static_cast<int>(Limb::LeftArm)) = a;
      W(v, static_cast<int>(Limb::Torso)) = 1 - a;
    }
    return W;
  }

  // The skeleton: the left arm down along the capsule, the right one out along −x.
  Eigen::MatrixX3d canonical() const {
    Eigen::MatrixX3d C = Eigen::MatrixX3d::Zero(kNumCanonical, 3);
    auto set = [&](Canonical c, const Vec3& p) { C.row(static_cast<int>(c)) = p.transpose(); };
    using K = Canonical;
    set(K::Pelvis, {0, 0, 0});
    set(K::Spine, {0, 0.2, 0});
    set(K::Chest, {0, 0.35, 0});
    set(K::Neck, {0, 0.5, 0});
    set(K::Head, {0, 0.65, 0});
    set(K::HeadTop, {0, 0.75, 0});
    set(K::Nose, {0, 0.65, 0.1});
    set(K::LeftClavicle, {0.05, 0.45, 0});
    set(K::LeftShoulder, shoulder);
    set(K::LeftElbow, shoulder + 0.28 * down);
    set(K::LeftWrist, shoulder + 0.5 * down);
    set(K::LeftHandTip, shoulder + 0.65 * down);
    set(K::RightClavicle, {-0.05, 0.45, 0});
    set(K::RightShoulder, {-0.2, 0.45, 0});
    set(K::RightElbow, {-0.45, 0.45, 0});
    set(K::RightWrist, {-0.7, 0.45, 0});
    set(K::RightHandTip, {-0.85, 0.45, 0});
    for (double s : {1.0, -1.0}) {
      const bool l = s > 0;
      set(l ? K::LeftHip : K::RightHip, {0.1 * s, -0.05, 0});
      set(l ? K::LeftKnee : K::RightKnee, {0.1 * s, -0.5, 0});
      set(l ? K::LeftAnkle : K::RightAnkle, {0.1 * s, -0.9, 0});
      set(l ? K::LeftHeel : K::RightHeel, {0.1 * s, -0.95, -0.05});
      set(l ? K::LeftToeTip : K::RightToeTip, {0.1 * s, -0.95, 0.15});
    }
    return C;
  }

  // The feature rules' armhole (body/features.cpp): a loop of 16 anchors round the arm 4 cm
  // below the shoulder joint, + on the chest's front and back.
  FeatureSet features() const {
    const MeshQuery q(bodyMesh);
    const auto on = [&](const Vec3& p) {
      const ClosestHit h = q.closestPoint(p);
      return SurfacePoint{h.face, h.bary};
    };
    FeatureSpline loop{"left_armhole", {}, true};
    const Vec3 u = down.cross(Vec3::UnitZ()).normalized(), w = Vec3::UnitZ();
    for (int i = 0; i < 16; ++i) {
      const double t = 2 * M_PI * i / 16;
      loop.anchors.push_back(
          on(shoulder + 0.04 * down + 0.05 * (std::cos(t) * u + std::sin(t) * w)));
    }
    CurveFeatures armhole{"shoulder", {loop}, {}};
    armhole.signs.push_back({"chest_front", on({0, 0.3, 0.14}), +1, -1});
    armhole.signs.push_back({"chest_back", on({0, 0.3, -0.14}), +1, -1});
    FeatureSet fs;
    fs.seams = {{"upper_side", {}, {}}, armhole};
    return fs;
  }
};

TEST(Armhole, ALoweredArmPressedToTheTrunkLeavesTheTrunkTrunkAndTheSleeveSleeve) {
  const ArmDownScene sc;
  const BodyFrame frame(sc.canonical());
  const MeshTopology topo(sc.shirt.F, sc.shirt.numVertices());
  const std::vector<Opening> openings = classifyOpenings(sc.shirt, topo, GarmentKind::Upper, frame);
  std::vector<std::string> names;
  for (const Opening& o : openings) names.push_back(o.name);
  std::sort(names.begin(), names.end());
  ASSERT_EQ(names, (std::vector<std::string>{"hem", "left_cuff", "neckline"}));

  // Where the shirt is known to be trunk and sleeve: 2 cm nearer one capsule than the other,
  // on the trunk below the arm's root, on the arm past 8 cm down it.
  std::vector<int> trunk, sleeve;
  for (int v = 0; v < sc.shirt.numVertices(); ++v) {
    const Vec3 p = sc.shirt.V.row(v).transpose();
    if (sc.trunk(p) < sc.arm(p) - 0.02 && p.x() > 0.1 && p.y() < 0.3) trunk.push_back(v);
    if (sc.arm(p) < sc.trunk(p) - 0.02 && sc.along(p) > 0.08) sleeve.push_back(v);
  }
  ASSERT_GT(trunk.size(), 100u);
  ASSERT_GT(sleeve.size(), 100u);
  // Vertices of the known trunk / sleeve on the wrong side of φ.
  const auto wrong = [](const SeamLine& s, const std::vector<int>& vs, double sign) {
    int n = 0;
    for (int v : vs) n += sign * s.phi[v] <= 0;
    return n;
  };

  const FeatureSet fs = sc.features();
  SeamOptions opt;
  opt.partMaxDistance = 0;  // the paper's constraints only
  const std::vector<SeamLine> paper =
      estimateSeams(sc.shirt, GarmentKind::Upper, sc.bodyMesh, fs, openings, opt);
  ASSERT_EQ(paper.size(), 2u);
  ASSERT_TRUE(paper[1].kept) << paper[1].removedWhy;
  // The paper's function: the cuff's −1 sits beside the trunk where the sleeve is joined to it,
  // the +1 constraints are far off (neckline, hem, chest): the trunk's side under the arm turns
  // sleeve even with every anchor kept.
  EXPECT_GT(wrong(paper[1], trunk, +1), static_cast<int>(trunk.size()) / 4);

  // Trunk points (the default): the trunk stays trunk.
  const Eigen::MatrixXd W = sc.limbWeight();
  const std::vector<SeamLine> seams =
      estimateSeams(sc.shirt, GarmentKind::Upper, sc.bodyMesh, fs, openings, {}, W);
  const SeamLine& s = seams[1];
  ASSERT_TRUE(s.kept) << s.removedWhy;
  EXPECT_GT(s.trunkPoints, 50);
  EXPECT_EQ(s.sleevePoints, 0);
  EXPECT_EQ(wrong(s, trunk, +1), 0) << "of " << trunk.size() << " trunk vertices";

  // With sleeve points too, the arm's inner side pressed to the trunk stays sleeve as well.
  SeamOptions both;
  both.sleeveArmWeight = 0.95;
  const std::vector<SeamLine> seams2 =
      estimateSeams(sc.shirt, GarmentKind::Upper, sc.bodyMesh, fs, openings, both, W);
  ASSERT_TRUE(seams2[1].kept) << seams2[1].removedWhy;
  EXPECT_GT(seams2[1].sleevePoints, 50);
  EXPECT_EQ(wrong(seams2[1], trunk, +1), 0) << "of " << trunk.size() << " trunk vertices";
  EXPECT_EQ(wrong(seams2[1], sleeve, -1), 0) << "of " << sleeve.size() << " sleeve vertices";
}

TEST(Armhole, AnArmHangingClearOfTheTrunkLeavesNoFoldUnderTheArmhole) {
  // 40°: the arm hangs clear of the trunk, the shirt's armpit is a rounded concave corner: no
  // stretch of the seam runs down a fold (the fused case: SeamContact's crease test).
  const ArmDownScene sc{.angle = 40 * M_PI / 180};
  const BodyFrame frame(sc.canonical());
  const MeshTopology topo(sc.shirt.F, sc.shirt.numVertices());
  const std::vector<Opening> openings = classifyOpenings(sc.shirt, topo, GarmentKind::Upper, frame);
  const std::vector<SeamLine> seams =
      estimateSeams(sc.shirt, GarmentKind::Upper, sc.bodyMesh, sc.features(), openings);
  ASSERT_EQ(seams.size(), 2u);
  ASSERT_TRUE(seams[1].kept) << seams[1].removedWhy;
  double top = -std::numeric_limits<double>::infinity(), low = -top;
  for (const SeamFold& f : armholeFolds(sc.shirt, seams[1]))
    for (const Vec3& p : {f.a, f.b}) {
      top = std::max(top, p.y());
      low = std::min(low, p.y());
    }
  EXPECT_LT(std::max(0.0, top - low), SeamOptions{}.creaseReportDrop);
}

TEST(Armhole, LimbWeightsSumEachVertexsSkinningOverTheLimbsJoints) {
  // Joints: 0 pelvis, 1 chest, 2 left clavicle, 3 left shoulder, 4 left elbow, 5 neck, 6 head.
  BodyModel m;
  m.parents = {-1, 0, 1, 2, 3, 1, 5};
  m.rest.V = Eigen::MatrixX3d::Zero(3, 3);
  m.canonical[static_cast<int>(Canonical::LeftShoulder)].joint = 3;
  m.canonical[static_cast<int>(Canonical::Neck)].joint = 5;
  std::vector<Eigen::Triplet<double>> w{{0, 1, 0.7}, {0, 2, 0.2}, {0, 3, 0.1},  // chest, clavicle
                                        {1, 3, 0.4}, {1, 4, 0.6},               // upper arm
                                        {2, 6, 0.5}, {2, 0, 0.5}};              // head, pelvis
  m.weights.resize(3, 7);
  m.weights.setFromTriplets(w.begin(), w.end());
  const Eigen::MatrixXd L = limbWeights(m);
  ASSERT_EQ(L.rows(), 3);
  ASSERT_EQ(L.cols(), 6);
  const int torso = static_cast<int>(Limb::Torso), arm = static_cast<int>(Limb::LeftArm),
            neck = static_cast<int>(Limb::Neck);
  EXPECT_NEAR(L(0, torso), 0.9, 1e-12);  // the clavicle is the trunk's
  EXPECT_NEAR(L(0, arm), 0.1, 1e-12);
  EXPECT_NEAR(L(1, arm), 1.0, 1e-12);
  EXPECT_NEAR(L(2, neck), 0.5, 1e-12);
  EXPECT_NEAR(L(2, torso), 0.5, 1e-12);
  EXPECT_NEAR(L.rowwise().sum().minCoeff(), 1.0, 1e-12);
  EXPECT_NEAR(L.rowwise().sum().maxCoeff(), 1.0, 1e-12);
}

}  // namespace
}  // namespace s2p
