// Feature rules checked geometrically on every available body source, in A-pose and T-pose:
// each boundary loop rings its limb's bone, sign points lie on their stated side, region
// points sit where their label says, seam sign points come in front/back (left/right) pairs.
#include "body/features.h"

#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>

#include "body/posing.h"
#include "body_test_sources.h"

namespace s2p {
namespace {

using Vec3 = Eigen::Vector3d;
using C = Canonical;

// === Geometry helpers

std::vector<Vec3> positions(const std::vector<SurfacePoint>& pts, const TriMesh& mesh) {
  std::vector<Vec3> out;
  for (const auto& p : pts) out.push_back(p.position(mesh));
  return out;
}

// Winding number of the closed polygon P around the line a→b, measured in the polygon's
// best-fit plane at the point where the line crosses it. Also returns the line parameter.
double windingAroundBone(const std::vector<Vec3>& P, const Vec3& a, const Vec3& b, double* t) {
  Vec3 c = Vec3::Zero();
  for (const auto& p : P) c += p;
  c /= static_cast<double>(P.size());
  Vec3 n = Vec3::Zero();
  for (size_t i = 0; i < P.size(); ++i) n += (P[i] - c).cross(P[(i + 1) % P.size()] - c);
  n.normalize();
  const Vec3 d = b - a;
  *t = (c - a).dot(n) / d.dot(n);
  const Vec3 x = a + *t * d;
  // Angle sum of the polygon projected on the plane.
  auto project = [&](const Vec3& p) -> Vec3 { return p - x - (p - x).dot(n) * n; };
  double total = 0;
  for (size_t i = 0; i < P.size(); ++i) {
    const Vec3 u = project(P[i]), v = project(P[(i + 1) % P.size()]);
    total += std::atan2(u.cross(v).dot(n), u.dot(v));
  }
  return total / (2 * M_PI);
}

Vec3 centroid(const std::vector<Vec3>& P) {
  Vec3 c = Vec3::Zero();
  for (const auto& p : P) c += p;
  return c / static_cast<double>(P.size());
}

const FeatureSpline& spline(const CurveFeatures& c, const std::string& name) {
  for (const auto& s : c.splines)
    if (s.name == name) return s;
  throw std::runtime_error("no spline " + name);
}
const SignPoint& sign(const CurveFeatures& c, const std::string& name) {
  for (const auto& s : c.signs)
    if (s.name == name) return s;
  throw std::runtime_error("no sign point " + name);
}

class FeatureRules : public ::testing::TestWithParam<StandardPose> {};

TEST_P(FeatureRules, LoopsRingTheirBonesAndSignsLieOnTheirSides_Slow) {
  for (const auto& src : test::bodySources()) {
    SCOPED_TRACE(src.name);
    const BodyModel& model = *src.model;
    const Eigen::VectorXd shape = Eigen::VectorXd::Zero(model.numShapes());
    const FeatureSet fs = computeFeatures(model, shape);
    const PosedBody body = poseBody(model, {shape, standardPose(model, shape, GetParam())});
    const TriMesh& mesh = body.mesh;
    auto J = [&](C c) -> Vec3 { return body.canonical.row(static_cast<int>(c)).transpose(); };
    auto P = [&](const SurfacePoint& p) { return p.position(mesh); };

    // Each loop encloses its bone once, and the bone crosses the loop's plane near the loop.
    const std::map<std::string, std::pair<C, C>> bones = {
        {"neck", {C::Neck, C::Head}},
        {"left_wrist", {C::LeftElbow, C::LeftWrist}},
        {"right_wrist", {C::RightElbow, C::RightWrist}},
        {"left_ankle", {C::LeftKnee, C::LeftAnkle}},
        {"right_ankle", {C::RightKnee, C::RightAnkle}},
        {"waist", {C::Pelvis, C::Neck}},
        {"left_armhole", {C::LeftShoulder, C::LeftElbow}},
        {"right_armhole", {C::RightShoulder, C::RightElbow}}};
    std::vector<const FeatureSpline*> loops;
    for (const auto* c : {&fs.upperSkin, &fs.lowerSkin, &fs.upperLower, fs.seam("shoulder")})
      for (const auto& s : c->splines) loops.push_back(&s);
    ASSERT_EQ(loops.size(), bones.size());
    for (const FeatureSpline* s : loops) {
      SCOPED_TRACE(s->name);
      ASSERT_TRUE(s->closed);
      const auto& [a, b] = bones.at(s->name);
      double t = 0;
      const double w = windingAroundBone(positions(s->anchors, mesh), J(a), J(b), &t);
      EXPECT_NEAR(std::abs(w), 1.0, 1e-9) << "t = " << t;
      EXPECT_GT(t, -0.3);
      EXPECT_LT(t, 1.3);
    }

    // B(U|S): nose and hand tips beyond the neck / wrist loops; chest points on the body side.
    const Vec3 neckC = centroid(positions(spline(fs.upperSkin, "neck").anchors, mesh));
    const Vec3 neckAxis = J(C::Head) - J(C::Neck);
    EXPECT_GT((P(sign(fs.upperSkin, "nose").point) - neckC).dot(neckAxis), 0);
    EXPECT_EQ(sign(fs.upperSkin, "nose").value, 1.0);
    for (const char* side : {"left", "right"}) {
      const bool left = std::string(side) == "left";
      const Vec3 wristC =
          centroid(positions(spline(fs.upperSkin, std::string(side) + "_wrist").anchors, mesh));
      const Vec3 foreArm =
          left ? J(C::LeftWrist) - J(C::LeftElbow) : J(C::RightWrist) - J(C::RightElbow);
      EXPECT_GT(
          (P(sign(fs.upperSkin, std::string(side) + "_hand_tip").point) - wristC).dot(foreArm), 0);
      for (const char* chest : {"chest_front", "chest_back"})
        EXPECT_LT((P(sign(fs.upperSkin, chest).point) - wristC).dot(foreArm), 0);
    }
    for (const char* chest : {"chest_front", "chest_back"}) {
      EXPECT_LT((P(sign(fs.upperSkin, chest).point) - neckC).dot(neckAxis), 0);
      EXPECT_EQ(sign(fs.upperSkin, chest).value, -1.0);
    }
    EXPECT_GT(P(sign(fs.upperSkin, "chest_front").point).z(),
              P(sign(fs.upperSkin, "chest_back").point).z());

    // B(L|S): toe tips and soles below the ankle loops.
    for (const char* side : {"left", "right"}) {
      const bool left = std::string(side) == "left";
      const Vec3 ankleC =
          centroid(positions(spline(fs.lowerSkin, std::string(side) + "_ankle").anchors, mesh));
      const Vec3 shin =
          left ? J(C::LeftKnee) - J(C::LeftAnkle) : J(C::RightKnee) - J(C::RightAnkle);
      for (const char* what : {"_toe_tip", "_sole"}) {
        const SignPoint& s = sign(fs.lowerSkin, std::string(side) + what);
        EXPECT_LT((P(s.point) - ankleC).dot(shin), 0) << s.name;
        EXPECT_EQ(s.value, 1.0);
      }
    }

    // B(U|L): chest points above the waist loop.
    const Vec3 waistC = centroid(positions(spline(fs.upperLower, "waist").anchors, mesh));
    const Vec3 spine = J(C::Neck) - J(C::Pelvis);
    for (const auto& s : fs.upperLower.signs) EXPECT_GT((P(s.point) - waistC).dot(spine), 0);

    // Regions: enough points of each label; upper above the waist, lower and foot below it,
    // foot below the ankle loops' mean height, skin on the head and hands.
    std::map<RegionLabel, int> count;
    for (const auto& r : fs.regions) {
      ++count[r.label];
      const Vec3 p = P(r.point);
      if (r.label == RegionLabel::Upper) {
        EXPECT_GT((p - waistC).dot(spine), 0);
      }
      if (r.label == RegionLabel::Lower || r.label == RegionLabel::Foot) {
        EXPECT_LT((p - waistC).dot(spine), 0);
      }
    }
    for (RegionLabel l :
         {RegionLabel::Skin, RegionLabel::Upper, RegionLabel::Lower, RegionLabel::Foot})
      EXPECT_GE(count[l], 20) << toString(l);

    // Seams: pair counts of §6.1.1, pairs mutual with opposite signs; front/back pairs have
    // the + point in front; crotch pairs have the + point on the left.
    const std::map<std::string, int> pairs = {
        {"upper_side", 13}, {"lower_side", 11}, {"crotch", 10}};
    for (const auto& [name, n] : pairs) {
      const CurveFeatures* seam = fs.seam(name);
      ASSERT_NE(seam, nullptr);
      ASSERT_EQ(static_cast<int>(seam->signs.size()), 2 * n) << name;
      for (int i = 0; i < static_cast<int>(seam->signs.size()); ++i) {
        const SignPoint& s = seam->signs[i];
        ASSERT_GE(s.pair, 0);
        EXPECT_EQ(seam->signs[s.pair].pair, i);
        EXPECT_EQ(seam->signs[s.pair].value, -s.value);
      }
    }
    for (const char* name : {"upper_side", "lower_side"})
      for (const auto& s : fs.seam(name)->signs) {
        // The + point is in front of its partner (A and T poses leave the torso facing +Z).
        if (s.value > 0) {
          EXPECT_GT(P(s.point).z(), P(fs.seam(name)->signs[s.pair].point).z()) << s.name;
        }
      }
    for (const auto& s : fs.seam("crotch")->signs)
      EXPECT_EQ(s.value > 0, P(s.point).x() > J(C::Pelvis).x()) << s.name;
    // Shoulder: + on the chest front and back, and the torso's sides below the arms (2 heights,
    // 3 points a side), on their side and below the shoulder joints; − on the arms' outer sides
    // (mid upper arm and mid forearm, 3 points each), farther out than the shoulder joint.
    EXPECT_EQ(fs.seam("shoulder")->signs.size(), 26u);
    for (const auto& s : fs.seam("shoulder")->signs) {
      const double side = s.name.find("_left_") != std::string::npos ? 1.0 : -1.0;
      if (s.name.rfind("arm_", 0) == 0) {
        EXPECT_LT(s.value, 0) << s.name;
        const C shoulder = side > 0 ? C::LeftShoulder : C::RightShoulder;
        EXPECT_GT(side * (P(s.point).x() - J(shoulder).x()), 0) << s.name;
        continue;
      }
      EXPECT_GT(s.value, 0) << s.name;
      if (s.name.rfind("torso_", 0) != 0) continue;
      EXPECT_GT(side * (P(s.point).x() - J(C::Pelvis).x()), 0) << s.name;
      EXPECT_LT(P(s.point).y(), std::min(J(C::LeftShoulder).y(), J(C::RightShoulder).y()) - 0.1)
          << s.name;
    }

    // Side seams stay on their side; the crotch seam runs front → crotch → back.
    for (const auto& s : fs.seam("upper_side")->splines) {
      const double side = s.name.rfind("left", 0) == 0 ? 1.0 : -1.0;
      for (const Vec3& p : positions(s.anchors, mesh))
        EXPECT_GT(side * (p.x() - J(C::Pelvis).x()), 0);
    }
    const auto crotch = positions(fs.seam("crotch")->splines.at(0).anchors, mesh);
    EXPECT_GT(crotch.front().z(), crotch.back().z());
    const double lowest = std::min_element(crotch.begin(), crotch.end(), [](auto& a, auto& b) {
                            return a.y() < b.y();
                          })->y();
    EXPECT_LT(lowest, J(C::Pelvis).y());
    EXPECT_GT(lowest, std::max(J(C::LeftKnee).y(), J(C::RightKnee).y()));
  }
}

INSTANTIATE_TEST_SUITE_P(Poses, FeatureRules,
                         ::testing::Values(StandardPose::APose, StandardPose::TPose),
                         [](const auto& info) {
                           return info.param == StandardPose::APose ? std::string("APose")
                                                                    : std::string("TPose");
                         });

TEST(FeatureSet, JsonRoundTripKeepsEveryPoint_Slow) {
  const BodyModel& model = *test::bodySources().front().model;
  const Eigen::VectorXd shape = Eigen::VectorXd::Zero(model.numShapes());
  const FeatureSet fs = computeFeatures(model, shape);
  const nlohmann::json j = featuresToJson(fs, model.rest);
  const FeatureSet back = featuresFromJson(nlohmann::json::parse(j.dump()));
  ASSERT_EQ(back.regions.size(), fs.regions.size());
  ASSERT_EQ(back.seams.size(), fs.seams.size());
  EXPECT_EQ(featuresToJson(back, model.rest), j);
}

TEST(FeatureSet, ShapeMovesTheFeaturesWithTheBody_Slow) {
  // Features are surface points on the same faces whatever the shape: a taller body carries
  // its neck loop up by about the change in neck height.
  const BodyModel& model = *test::bodySources().front().model;
  Eigen::VectorXd shape = Eigen::VectorXd::Zero(model.numShapes());
  const FeatureSet base = computeFeatures(model, shape);
  shape(0) = 5;  // mannequin: height +5 cm
  const FeatureSet tall = computeFeatures(model, shape);
  const TriMesh restTall{shapedTemplate(model, shape), model.rest.F};
  const double yBase = centroid(positions(base.upperSkin.splines[0].anchors, model.rest)).y();
  const double yTall = centroid(positions(tall.upperSkin.splines[0].anchors, restTall)).y();
  EXPECT_NEAR(yTall - yBase, 0.05 * 1.45 / 1.75, 0.01);
}

}  // namespace
}  // namespace s2p
