// Keypoint files: the canonical-name map round-trips, OpenPose BODY_25 rows land on the right
// canonical joints with zero rows dropped (not averaged), the file-to-scan transform is applied,
// and each bad file throws its documented error type.
#include "fit/keypoints.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "test_support.h"

namespace s2p {
namespace {

using nlohmann::json;

const JointTarget* find(const std::vector<JointTarget>& targets, Canonical c) {
  for (const JointTarget& t : targets)
    if (t.joint == c) return &t;
  return nullptr;
}

// 25 rows: row i at (i, 2i, 3i) with score 0.5 + i/100; rows listed in `zero` are all zeros.
json body25(const std::vector<int>& zero = {}) {
  json flat = json::array();
  for (int i = 0; i < kBody25Count; ++i) {
    const bool z = std::find(zero.begin(), zero.end(), i) != zero.end();
    for (double v : {double(i), 2.0 * i, 3.0 * i, 0.5 + i / 100.0}) flat.push_back(z ? 0.0 : v);
  }
  return {{"version", 1.3}, {"people", {{{"person_id", {-1}}, {"pose_keypoints_3d", flat}}}}};
}

std::filesystem::path put(const test::TempDir& dir, const std::string& name,
                          const std::string& text) {
  test::writeFile(dir / name, text);
  return dir / name;
}

TEST(Keypoints, Body25NamesAndMapping) {
  EXPECT_STREQ(body25Name(0), "Nose");
  EXPECT_STREQ(body25Name(8), "MidHip");
  EXPECT_STREQ(body25Name(24), "RHeel");
  EXPECT_EQ(body25ToCanonical(1), Canonical::Neck);
  EXPECT_EQ(body25ToCanonical(4), Canonical::RightWrist);
  EXPECT_EQ(body25ToCanonical(7), Canonical::LeftWrist);
  EXPECT_EQ(body25ToCanonical(8), Canonical::Pelvis);
  EXPECT_EQ(body25ToCanonical(13), Canonical::LeftKnee);
  EXPECT_EQ(body25ToCanonical(19), Canonical::LeftToeTip);
  EXPECT_EQ(body25ToCanonical(22), Canonical::RightToeTip);
  EXPECT_EQ(body25ToCanonical(21), Canonical::LeftHeel);
  for (int i : {15, 16, 17, 18, 20, 23}) EXPECT_FALSE(body25ToCanonical(i)) << i;
  EXPECT_FALSE(body25ToCanonical(25));
  // No canonical joint is the image of two BODY_25 points.
  std::map<int, int> count;
  for (int i = 0; i < kBody25Count; ++i)
    if (auto c = body25ToCanonical(i)) ++count[static_cast<int>(*c)];
  EXPECT_EQ(count.size(), 19u);
  for (const auto& [c, n] : count) EXPECT_EQ(n, 1) << toString(static_cast<Canonical>(c));
}

TEST(Keypoints, MapRoundTrips) {
  test::TempDir dir;
  const std::map<Canonical, Eigen::Vector3d> truth = {{Canonical::LeftWrist, {0.7, 1.0, 0.05}},
                                                      {Canonical::RightWrist, {-0.7, 1.0, 0.05}},
                                                      {Canonical::Head, {0, 1.6, 0}},
                                                      {Canonical::LeftAnkle, {0.1, 0.08, 0}},
                                                      {Canonical::RightAnkle, {-0.1, 0.08, 0}}};
  json j;
  for (const auto& [c, p] : truth) j[toString(c)] = {p.x(), p.y(), p.z()};
  for (const json& doc : {j, json{{"joints", j}}}) {
    const auto targets = readKeypoints(put(dir, "k.json", doc.dump()), Eigen::Affine3d::Identity());
    ASSERT_EQ(targets.size(), truth.size());
    for (const auto& [c, p] : truth) {
      const JointTarget* t = find(targets, c);
      ASSERT_NE(t, nullptr) << toString(c);
      EXPECT_LT((t->position - p).norm(), 1e-12) << toString(c);
      EXPECT_EQ(t->weight, 1.0);
    }
  }
}

TEST(Keypoints, MapWeightsAndUndetectedEntries) {
  test::TempDir dir;
  const json j = {{"head", {0, 1.6, 0, 0.5}},   {"pelvis", {0, 0.9, 0}},
                  {"left_knee", {0.1, 0.5, 0}}, {"right_knee", {-0.1, 0.5, 0, 0}},
                  {"left_wrist", nullptr},      {"right_wrist", {-0.7, 1, 0}}};
  const auto targets = readKeypoints(put(dir, "k.json", j.dump()), Eigen::Affine3d::Identity());
  EXPECT_EQ(targets.size(), 4u);
  EXPECT_EQ(find(targets, Canonical::Head)->weight, 0.5);
  EXPECT_EQ(find(targets, Canonical::RightKnee), nullptr);
  EXPECT_EQ(find(targets, Canonical::LeftWrist), nullptr);
}

TEST(Keypoints, OpenPoseRowsMapToCanonicalJointsAndZeroRowsAreDropped) {
  test::TempDir dir;
  // Rows 4 (RWrist) and 21 (LHeel) not detected.
  const auto targets =
      readKeypoints(put(dir, "op.json", body25({4, 21}).dump()), Eigen::Affine3d::Identity());
  // 19 BODY_25 points have a canonical joint; two of them are undetected.
  EXPECT_EQ(targets.size(), 17u);
  EXPECT_EQ(find(targets, Canonical::RightWrist), nullptr);
  EXPECT_EQ(find(targets, Canonical::LeftHeel), nullptr);
  const std::map<int, Canonical> expected = {
      {0, Canonical::Nose},       {1, Canonical::Neck},         {2, Canonical::RightShoulder},
      {7, Canonical::LeftWrist},  {8, Canonical::Pelvis},       {9, Canonical::RightHip},
      {14, Canonical::LeftAnkle}, {22, Canonical::RightToeTip}, {24, Canonical::RightHeel}};
  for (const auto& [i, c] : expected) {
    const JointTarget* t = find(targets, c);
    ASSERT_NE(t, nullptr) << toString(c);
    EXPECT_LT((t->position - Eigen::Vector3d(i, 2 * i, 3 * i)).norm(), 1e-12) << toString(c);
    EXPECT_NEAR(t->weight, 0.5 + i / 100.0, 1e-15) << toString(c);
  }
  // Nothing lands at the origin: a zero row never becomes a target.
  for (const JointTarget& t : targets)
    if (t.joint != Canonical::Nose) {
      EXPECT_GT(t.position.norm(), 0.5) << toString(t.joint);
    }
}

TEST(Keypoints, TransformIsApplied) {
  test::TempDir dir;
  // File in millimetres, +Z up: normalised = R·(p/1000) + offset.
  Eigen::Affine3d toNorm = Eigen::Affine3d::Identity();
  toNorm.translate(Eigen::Vector3d(0.1, -0.2, 0.3));
  toNorm.rotate(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  toNorm.scale(0.001);
  const json j = {{"head", {0, 10, 1600}},
                  {"pelvis", {0, 0, 900}},
                  {"left_ankle", {100, 0, 80}},
                  {"right_ankle", {-100, 0, 80}}};
  const auto targets = readKeypoints(put(dir, "k.json", j.dump()), toNorm);
  ASSERT_EQ(targets.size(), 4u);
  // Rotating −90° about X takes +Z to +Y and +Y to −Z.
  EXPECT_LT((find(targets, Canonical::Head)->position - Eigen::Vector3d(0.1, 1.4, 0.29)).norm(),
            1e-12);
  EXPECT_LT(
      (find(targets, Canonical::LeftAnkle)->position - Eigen::Vector3d(0.2, -0.12, 0.3)).norm(),
      1e-12);
  // The same transform on BODY_25 rows.
  const auto op = readKeypoints(put(dir, "op.json", body25().dump()), toNorm);
  const Eigen::Vector3d neck(1, 2, 3);
  EXPECT_LT((find(op, Canonical::Neck)->position - toNorm * neck).norm(), 1e-12);
}

TEST(Keypoints, BadFilesThrowTheirTypes) {
  test::TempDir dir;
  const Eigen::Affine3d id = Eigen::Affine3d::Identity();
  const auto read = [&](const std::string& text) {
    return readKeypoints(put(dir, "bad.json", text), id);
  };
  EXPECT_THROW(readKeypoints(dir / "missing.json", id), IoError);
  EXPECT_THROW(readKeypoints(dir.path(), id), IoError);  // a folder
  try {
    readKeypoints(dir / "missing.json", id);
  } catch (const FormatError&) {
    ADD_FAILURE() << "a missing file is not a format error";
  } catch (const IoError&) {
  }
  EXPECT_THROW(read("{ not json"), FormatError);
  EXPECT_THROW(read("[1, 2, 3]"), FormatError);
  EXPECT_THROW(read(R"({"joints": [1, 2]})"), FormatError);
  EXPECT_THROW(
      read(R"({"head": [0, 1], "pelvis": [0,0,0], "left_knee": [0,0,0], "right_knee": [0,0,0]})"),
      FormatError);
  EXPECT_THROW(
      read(
          R"({"head": [0, "1", 0], "pelvis": [0,0,0], "left_knee": [0,0,0], "right_knee": [0,0,0]})"),
      FormatError);
  // 1e999 parses as infinity.
  EXPECT_THROW(
      read(
          R"({"head": [0, 1e999, 0], "pelvis": [0,0,0], "left_knee": [0,0,0], "right_knee": [0,0,0]})"),
      FormatError);
  try {
    read(R"({"head": [0, 1, 0], "left_pinky": [0, 0, 0]})");
    ADD_FAILURE() << "unknown name accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("left_pinky"), std::string::npos) << e.what();
  }
  try {
    read(R"({"head": [0, 1.6, 0], "pelvis": [0, 0.9, 0], "left_knee": null})");
    ADD_FAILURE() << "three joints accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("only 2 usable"), std::string::npos) << e.what();
  }
  // OpenPose: no person, only 2D, wrong row count, a non-number, a non-finite row, too few rows
  // detected.
  EXPECT_THROW(read(R"({"people": []})"), InputError);
  EXPECT_THROW(read(R"({"people": [{"pose_keypoints_2d": [1, 2, 0.5], "pose_keypoints_3d": []}]})"),
               FormatError);
  json j = body25();
  j["people"][0]["pose_keypoints_3d"].erase(0);
  EXPECT_THROW(read(j.dump()), FormatError);
  j = body25();
  j["people"][0]["pose_keypoints_3d"][5] = "x";
  EXPECT_THROW(read(j.dump()), FormatError);
  std::string inf = body25().dump();
  inf.replace(inf.find("[0.0,0.0,0.0,0.5"), 16, "[0.0,1e999,0.0,0.5");
  EXPECT_THROW(read(inf), FormatError);
  std::vector<int> zero;
  for (int i = 0; i < kBody25Count; ++i)
    if (i != 1 && i != 8 && i != 15) zero.push_back(i);
  try {
    read(body25(zero).dump());
    ADD_FAILURE() << "two detected joints accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("neck, pelvis"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace s2p
