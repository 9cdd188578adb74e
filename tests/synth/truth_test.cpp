// truth.json: the round trip keeps every field, and malformed files give FormatError (missing
// files IoError) naming the entry.
#include "synth/truth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "core/error.h"
#include "test_support.h"

namespace s2p {
namespace {

Truth sampleTruth() {
  Truth t;
  t.preset = "tshirt_trousers";
  t.seed = 12345678901234ULL;
  t.scanFile = "scan.ply";
  t.labelledMesh = "labels.ply";
  t.garments.push_back({"t-shirt", "tshirt", Label::Upper, false, {"trousers"}, 0.61, {}, {}});
  t.garments.push_back({"trousers", "trousers", Label::Lower, false, {}, 0.83, {}, {}});
  t.garments.push_back({"dress", "dress", Label::Upper, true, {}, 0.0, {}, {}});
  t.body = {{"source", "mannequin"}, {"canonical", {{"pelvis", {0.0, 0.95, 0.01}}}}};
  TrueBoundary waist;
  waist.a = Label::Upper;
  waist.b = Label::Lower;
  Eigen::MatrixX3d loop(4, 3);
  loop << 0.1, 1.0, 0.0, 0.0, 1.0, 0.1, -0.1, 1.0, 0.0, 0.0, 1.0, -0.1 / 3;
  Eigen::MatrixX3d open(2, 3);
  open << 0.2, 0.5, 0.0, 0.2, 0.4, 1e-7;
  waist.curves = {loop, open};
  waist.closed = {true, false};
  t.boundaries.push_back(waist);
  TrueBoundary neck;
  neck.a = Label::Skin;
  neck.b = Label::Upper;
  t.boundaries.push_back(neck);  // no curves
  t.generator = {{"vertices", 50000}};
  return t;
}

void expectEqual(const Truth& a, const Truth& b) {
  EXPECT_EQ(a.preset, b.preset);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.scanFile, b.scanFile);
  EXPECT_EQ(a.labelledMesh, b.labelledMesh);
  EXPECT_EQ(a.frame, b.frame);
  ASSERT_EQ(a.garments.size(), b.garments.size());
  for (std::size_t i = 0; i < a.garments.size(); ++i) {
    EXPECT_EQ(a.garments[i].name, b.garments[i].name);
    EXPECT_EQ(a.garments[i].type, b.garments[i].type);
    EXPECT_EQ(a.garments[i].label, b.garments[i].label);
    EXPECT_EQ(a.garments[i].onePiece, b.garments[i].onePiece);
    EXPECT_EQ(a.garments[i].occludes, b.garments[i].occludes);
    EXPECT_EQ(a.garments[i].visibleArea, b.garments[i].visibleArea);
  }
  EXPECT_EQ(a.body, b.body);
  ASSERT_EQ(a.boundaries.size(), b.boundaries.size());
  for (std::size_t i = 0; i < a.boundaries.size(); ++i) {
    EXPECT_EQ(a.boundaries[i].a, b.boundaries[i].a);
    EXPECT_EQ(a.boundaries[i].b, b.boundaries[i].b);
    EXPECT_EQ(a.boundaries[i].closed, b.boundaries[i].closed);
    ASSERT_EQ(a.boundaries[i].curves.size(), b.boundaries[i].curves.size());
    for (std::size_t c = 0; c < a.boundaries[i].curves.size(); ++c)
      EXPECT_EQ(a.boundaries[i].curves[c], b.boundaries[i].curves[c]);  // bit-exact
  }
  EXPECT_EQ(a.generator, b.generator);
}

TEST(Truth, JsonRoundTripIsExact) {
  const Truth t = sampleTruth();
  const nlohmann::json j = truthToJson(t);
  expectEqual(t, truthFromJson(nlohmann::json::parse(j.dump())));
  // length_m is written for readers; the loop's closing segment counts.
  const double expected =
      2 * std::sqrt(0.02) + 2 * std::sqrt(0.01 + 0.01 / 9) + std::sqrt(0.01 + 1e-14);
  EXPECT_NEAR(j["boundaries"][0]["length_m"].get<double>(), expected, 1e-14);
  EXPECT_EQ(j["label_codes"]["gap"].get<int>(), 6);
}

TEST(Truth, FileRoundTrip) {
  test::TempDir dir;
  const Truth t = sampleTruth();
  writeTruth(dir / "truth.json", t);
  expectEqual(t, readTruth(dir / "truth.json"));
}

TEST(Truth, BoundaryListRoundTripAndOrder) {
  const Truth t = sampleTruth();
  const std::vector<TrueBoundary> back = boundariesFromJson(boundariesToJson(t.boundaries));
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].curves[1], t.boundaries[0].curves[1]);
  // Labels given as ["lower", "upper"] are stored as a < b.
  nlohmann::json j = boundariesToJson(t.boundaries);
  j[0]["labels"] = {"lower", "upper"};
  const std::vector<TrueBoundary> swapped = boundariesFromJson(j);
  EXPECT_EQ(swapped[0].a, Label::Upper);
  EXPECT_EQ(swapped[0].b, Label::Lower);
}

// Mutates a good truth.json and expects FormatError whose message names `mentions`.
void expectFormatError(const std::function<void(nlohmann::json&)>& mutate,
                       const std::string& mentions) {
  nlohmann::json j = truthToJson(sampleTruth());
  mutate(j);
  try {
    truthFromJson(j, "bad.json");
    ADD_FAILURE() << "no error for " << mentions;
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find(mentions), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  }
}

TEST(Truth, MalformedEntriesAreFormatErrors) {
  expectFormatError([](auto& j) { j.erase("boundaries"); }, "boundaries");
  expectFormatError([](auto& j) { j["boundaries"] = 3; }, "boundaries");
  expectFormatError([](auto& j) { j["seed"] = "many"; }, "seed");
  expectFormatError([](auto& j) { j["garments"][1]["label"] = "sleeve"; }, "garment 1");
  expectFormatError([](auto& j) { j["boundaries"][0]["labels"] = {"upper"}; }, "boundary 0");
  expectFormatError(
      [](auto& j) {
        j["boundaries"][0]["labels"] = {"upper", "upper"};
      },
      "boundary 0");
  expectFormatError(
      [](auto& j) {
        j["boundaries"][0]["curves"][0]["points"][2] = {1.0, 2.0};
      },
      "point 2 of curve 0 of boundary 0");
  expectFormatError([](auto& j) { j["boundaries"][0]["curves"][1].erase("closed"); },
                    "curve 1 of boundary 0");
  expectFormatError([](auto& j) { j = nlohmann::json::array(); }, "preset");
}

TEST(Truth, BadFiles) {
  test::TempDir dir;
  try {
    readTruth(dir / "missing.json");
    FAIL() << "no error";
  } catch (const FormatError&) {
    FAIL() << "a missing file is an IoError, not a FormatError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.json"), std::string::npos) << e.what();
  }
  test::writeFile(dir / "garbage.json", "{\"preset\": ");
  EXPECT_THROW(readTruth(dir / "garbage.json"), FormatError);
  test::writeFile(dir / "empty.json", "");
  EXPECT_THROW(readTruth(dir / "empty.json"), FormatError);
}

}  // namespace
}  // namespace s2p
