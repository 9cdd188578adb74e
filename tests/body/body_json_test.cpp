#include "body/body_json.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// Four joints up a stretched icosphere, two-joint inverse-distance skinning, each joint
// regressed from its three nearest vertices, three named shape directions.
BodyModel makeModel() {
  BodyModel m;
  m.source = "json-test";
  m.rest = makeIcosphere(2, 0.5);
  m.rest.V.col(1) *= 3.0;
  const int nv = m.numVertices(), nj = 4;
  m.parents = {-1, 0, 1, 2};
  m.jointNames = {"root", "lower", "upper", "top"};
  std::vector<Eigen::Vector3d> J;
  for (int j = 0; j < nj; ++j) J.emplace_back(0, -1.2 + 0.8 * j, 0);
  std::vector<Eigen::Triplet<double>> tw, tr;
  for (int v = 0; v < nv; ++v) {
    std::vector<std::pair<double, int>> d;
    for (int j = 0; j < nj; ++j) d.push_back({(m.rest.V.row(v).transpose() - J[j]).norm(), j});
    std::sort(d.begin(), d.end());
    const double a = 1 / (d[0].first + 0.01), b = 1 / (d[1].first + 0.01);
    tw.emplace_back(v, d[0].second, a / (a + b));
    tw.emplace_back(v, d[1].second, b / (a + b));
  }
  for (int j = 0; j < nj; ++j) {
    std::vector<std::pair<double, int>> d;
    for (int v = 0; v < nv; ++v) d.push_back({(m.rest.V.row(v).transpose() - J[j]).norm(), v});
    std::sort(d.begin(), d.end());
    for (int k = 0; k < 3; ++k) tr.emplace_back(j, d[k].second, 1.0 / 3);
  }
  m.weights.resize(nv, nj);
  m.weights.setFromTriplets(tw.begin(), tw.end());
  m.jointRegressor.resize(nj, nv);
  m.jointRegressor.setFromTriplets(tr.begin(), tr.end());
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> U(-0.02, 0.02);
  m.shapeDirs.resize(3 * nv, 3);
  for (int i = 0; i < m.shapeDirs.size(); ++i) m.shapeDirs.data()[i] = U(rng);
  m.shapeParams = {{"height", "+1 = +1 cm", -5, 5}, {"chest", "", -5, 5}, {"waist", "", -5, 5}};
  for (int c = 0; c < kNumCanonical; ++c) {
    if (c < 19)
      m.canonical[c].joint = c % nj;
    else
      m.canonical[c].vertices = {{c, 0.5}, {c + 40, 0.5}};
  }
  return m;
}

BodyParams someParams(const BodyModel& m) {
  BodyParams p;
  p.shape = Eigen::Vector3d(0.1234567890123, -2.5, 1.0 / 3.0);
  p.pose = BodyPose::zero(m.numJoints());
  p.pose.axisAngle << 0.1, 0.2, 0.3, -0.7, 0, 1e-17, 0, 0, 0, 2.0, -1.0, 0.5;
  p.pose.translation = Eigen::Vector3d(0.5, -1.0 / 7.0, 3.0);
  return p;
}

TEST(BodyJson, RoundTripThroughTextIsExact) {
  const BodyModel m = makeModel();
  ASSERT_NO_THROW(m.validate());
  const BodyParams p = someParams(m);
  const PosedBody posed = poseBody(m, p);
  const std::string text = bodyToJson(m, p, posed).dump(2);
  const nlohmann::json j = nlohmann::json::parse(text);
  const BodyParams back = bodyParamsFromJson(j, m);
  EXPECT_EQ(back.shape, p.shape);
  EXPECT_EQ(back.pose.axisAngle, p.pose.axisAngle);
  EXPECT_EQ(back.pose.translation, p.pose.translation);
  // Everything by name.
  EXPECT_EQ(j["source"], "json-test");
  EXPECT_DOUBLE_EQ(j["shape"]["chest"].get<double>(), -2.5);
  EXPECT_DOUBLE_EQ(j["pose"]["lower"][0].get<double>(), -0.7);
  for (int k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(j["joints"]["upper"][k].get<double>(), posed.joints(2, k));
    EXPECT_DOUBLE_EQ(j["canonical"]["nose"][k].get<double>(),
                     posed.canonical(static_cast<int>(Canonical::Nose), k));
  }
  EXPECT_EQ(j["canonical"].size(), static_cast<size_t>(kNumCanonical));
  EXPECT_EQ(j["joints"].size(), 4u);
  // Posing the parameters read back reproduces the recorded joints.
  const PosedBody again = poseBody(m, back);
  EXPECT_EQ(again.joints, posed.joints);
}

TEST(BodyJson, PartialInputDefaultsToZeroAndAcceptsCanonicalNames) {
  const BodyModel m = makeModel();
  const nlohmann::json j = nlohmann::json::parse(R"({"shape": {"waist": 2},
      "pose": {"pelvis": [0.5, 0, 0]}})");
  const BodyParams p = bodyParamsFromJson(j, m);
  EXPECT_EQ(p.shape, Eigen::Vector3d(0, 0, 2));
  EXPECT_DOUBLE_EQ(p.pose.axisAngle(0, 0), 0.5);  // pelvis → joint 0 by the canonical map
  EXPECT_DOUBLE_EQ(p.pose.axisAngle.cwiseAbs().sum(), 0.5);
  EXPECT_TRUE(p.pose.translation.isZero(0.0));
}

TEST(BodyJson, BadNamesAndValuesAreInputErrorsNamingThem) {
  const BodyModel m = makeModel();
  auto message = [&](const char* text) -> std::string {
    try {
      bodyParamsFromJson(nlohmann::json::parse(text), m);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  EXPECT_NE(message(R"({"shape": {"hips": 1}})").find("hips"), std::string::npos);
  EXPECT_NE(message(R"({"pose": {"tail": [0, 0, 0]}})").find("tail"), std::string::npos);
  EXPECT_NE(message(R"({"pose": {"top": [0, 0]}})").find("top"), std::string::npos);
  EXPECT_NE(message(R"({"translation": [0, "a", 0]})").find("translation"), std::string::npos);
  EXPECT_NE(message(R"({"shape": {"chest": "big"}})").find("chest"), std::string::npos);
  EXPECT_NE(message(R"([1, 2])"), "(accepted)");
}

}  // namespace
}  // namespace s2p
