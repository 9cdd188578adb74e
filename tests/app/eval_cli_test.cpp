// `scan2pattern eval`: the truth against itself scores 1, a shifted labelling its known figures,
// and missing or foreign inputs get their exit codes.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "cli_support.h"
#include "core/shapes.h"
#include "io/write_mesh.h"
#include "test_support.h"

namespace s2p {
namespace {

using EvalRun = test::CliRun;

// Runs the command with the arguments (each quoted), stderr captured unless left out.
EvalRun runApp(const std::vector<std::string>& args, bool withStderr = true) {
  std::string line;
  for (const std::string& a : args) line += test::q(a) + " ";
  return test::runCli(line, withStderr);
}

constexpr int kRings = 50, kSegments = 32;
constexpr double kRadius = 0.15, kHeight = 1.0;

// Cylinder faces labelled skin (0) below y = h, upper (1) above.
Eigen::VectorXi labelsBelowAbove(const TriMesh& m, double h) {
  Eigen::VectorXi l(m.numFaces());
  for (int f = 0; f < m.numFaces(); ++f)
    l(f) = (m.V(m.F(f, 0), 1) + m.V(m.F(f, 1), 1) + m.V(m.F(f, 2), 1)) / 3 > h ? 1 : 0;
  return l;
}

nlohmann::json circle(double y) {
  nlohmann::json pts = nlohmann::json::array();
  for (int s = 0; s < kSegments; ++s) {
    const double phi = 2 * std::numbers::pi * s / kSegments;
    pts.push_back({kRadius * std::sin(phi), y, kRadius * std::cos(phi)});
  }
  return {{"labels", {"skin", "upper"}}, {"curves", {{{"closed", true}, {"points", pts}}}}};
}

// truth.json + labels.ply in dir: skin | upper at 0.5, a body with one canonical joint.
void writeTruthFiles(const test::TempDir& dir, const TriMesh& m) {
  const Eigen::VectorXi fl = labelsBelowAbove(m, 0.5);
  writePly(dir / "labels.ply", m, {.faceLabels = &fl});
  nlohmann::json t = {{"preset", "custom"},
                      {"seed", 1},
                      {"scan", "labels.ply"},
                      {"labelled_mesh", "labels.ply"},
                      {"garments", nlohmann::json::array()},
                      {"body", {{"canonical", {{"pelvis", {0.0, 0.9, 0.0}}}}}},
                      {"boundaries", {circle(0.5)}}};
  test::writeFile(dir / "truth.json", t.dump());
}

TEST(EvalCli, TruthAgainstItselfScoresOne) {
  test::TempDir dir;
  const TriMesh m = makeCylinder(kRings, kSegments, kRadius, kHeight);
  writeTruthFiles(dir, m);
  const EvalRun r = runApp({"eval", "--truth", dir / "truth.json", "--pred", dir / "labels.ply"});
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("1.000"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("missing"), std::string::npos) << r.out;
  const EvalRun js = runApp(
      {"-q", "eval", "--json", "--truth", dir / "truth.json", "--pred", dir / "labels.ply"}, false);
  ASSERT_EQ(js.code, 0) << js.out;
  const auto j = nlohmann::json::parse(js.out);
  EXPECT_DOUBLE_EQ(j["labels"]["upper"]["iou"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["labels"]["skin"]["iou"].get<double>(), 1.0);
  EXPECT_NEAR(j["boundaries"][0]["pooled"]["mean_mm"].get<double>(), 0.0, 1e-6);
  EXPECT_FALSE(j.contains("body"));
}

TEST(EvalCli, FolderWithBoundariesAndBodyGivesKnownFigures) {
  test::TempDir dir;
  const TriMesh m = makeCylinder(kRings, kSegments, kRadius, kHeight);
  writeTruthFiles(dir, m);
  std::filesystem::create_directory(dir / "pred");
  const Eigen::VectorXi fl = labelsBelowAbove(m, 0.54);  // two rings (4 cm) higher
  writePly(dir / "pred" / "segmentation.ply", m, {.faceLabels = &fl});
  test::writeFile(dir / "pred" / "boundaries.json",
                  nlohmann::json{{"boundaries", {circle(0.54)}}}.dump());
  test::writeFile(dir / "pred" / "body.json",
                  nlohmann::json{{"canonical", {{"pelvis", {0.0, 0.906, 0.008}}}}}.dump());
  const EvalRun r = runApp(
      {"-q", "eval", "--json", "--truth", dir / "truth.json", "--pred", dir / "pred"}, false);
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["labels"]["upper"]["iou"].get<double>(), 0.46 / 0.5, 1e-9);
  EXPECT_EQ(j["boundary_source"].get<std::string>(), "curves");
  EXPECT_NEAR(j["boundaries"][0]["pooled"]["mean_mm"].get<double>(), 40.0, 1e-3);
  EXPECT_NEAR(j["boundaries"][0]["roughness"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(j["body"]["mean_error_mm"].get<double>(), 10.0, 1e-6);
}

TEST(EvalCli, MissingOrForeignInputsGetTheirExitCodes) {
  test::TempDir dir;
  const TriMesh m = makeCylinder(kRings, kSegments, kRadius, kHeight);
  writeTruthFiles(dir, m);
  const std::string truth = dir / "truth.json";
  EvalRun r = runApp({"eval", "--truth", truth, "--pred", dir / "nothing.ply"});
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("nothing.ply"), std::string::npos) << r.out;
  std::filesystem::create_directory(dir / "empty");
  r = runApp({"eval", "--truth", truth, "--pred", dir / "empty"});
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("segmentation.ply"), std::string::npos) << r.out;
  r = runApp({"eval", "--truth", dir / "no_truth.json", "--pred", dir / "labels.ply"});
  EXPECT_EQ(r.code, 3) << r.out;
  r = runApp(
      {"eval", "--truth", truth, "--pred", dir / "labels.ply", "--body", dir / "no_body.json"});
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_EQ(runApp({"eval", "--pred", dir / "labels.ply"}).code, 2);  // --truth required

  // Another scan: the same cylinder half a metre away.
  TriMesh other = m;
  other.V.col(0).array() += 0.5;
  const Eigen::VectorXi fl = labelsBelowAbove(other, 0.5);
  writePly(dir / "other.ply", other, {.faceLabels = &fl});
  r = runApp({"eval", "--truth", truth, "--pred", dir / "other.ply"});
  EXPECT_EQ(r.code, 5) << r.out;
  EXPECT_NE(r.out.find("another scan"), std::string::npos) << r.out;

  test::writeFile(dir / "garbage.ply", "ply\nformat nonsense\n");
  EXPECT_EQ(runApp({"eval", "--truth", truth, "--pred", dir / "garbage.ply"}).code, 4);
}

}  // namespace
}  // namespace s2p
