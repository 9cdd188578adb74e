// `scan2pattern fit` and `run` end to end: a fitted body that `segment --body` and `eval --body`
// accept and that lies where the truth's body is, and the refusals that leave no output behind.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_support.h"
#include "core/shapes.h"
#include "io/write_mesh.h"
#include "test_support.h"

namespace s2p {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::q;
using test::readJson;

// The fit's body.json feeds segment --body; eval scores both against the truth. The scan is
// turned by 120° about the vertical, so body.json's frame (to_scan_file) is exercised.
TEST(FitCli, FittedBodyFeedsSegmentAndMatchesTheTruth_Slow) {
  test::TempDir dir;
  CliRun r =
      test::runCli("-q synth --preset tshirt_trousers --seed 5 --vertices 9000 --yaw 120 -o " +
                   q(dir / "synth"));
  ASSERT_EQ(r.code, 0) << r.out;
  r = test::runCli("-q fit " + q(dir / "synth" / "scan.ply") + " --no-nonrigid -o " +
                   q(dir / "fit"));
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* name :
       {"body_fit.obj", "body_full.obj", "body.json", "fit_front.png", "fit_side.png"})
    EXPECT_TRUE(fs::exists(dir / "fit" / name)) << name;
  const nlohmann::json body = readJson(dir / "fit" / "body.json");
  EXPECT_EQ(body["source"], "mannequin");
  EXPECT_TRUE(body.contains("to_scan_file"));
  EXPECT_GT(body["measurements"]["height"].get<double>(), 1.5);

  r = test::runCli("-q segment " + q(dir / "synth" / "scan.ply") + " --body " +
                   q(dir / "fit" / "body.json") + " -o " + q(dir / "seg"));
  ASSERT_EQ(r.code, 0) << r.out;
  r = test::runCli("eval --truth " + q(dir / "synth" / "truth.json") + " --pred " + q(dir / "seg") +
                       " --body " + q(dir / "fit" / "body.json") + " --json",
                   false);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json e = nlohmann::json::parse(r.out);
  EXPECT_GE(e["mean_garment_iou"].get<double>(), 0.95);
  EXPECT_LT(e["body"]["mean_error_mm"].get<double>(), 30.0);
  EXPECT_LT(e["body"]["max_error_mm"].get<double>(), 60.0);

  // Keypoints from outside (here: eight of the true joints, in the scan file's frame) start the
  // pose instead of the scan's extremities and lead to the same body.
  const nlohmann::json truth = readJson(dir / "synth" / "truth.json");
  nlohmann::json keypoints;
  for (const char* j : {"pelvis", "neck", "left_wrist", "right_wrist", "left_elbow", "right_elbow",
                        "left_ankle", "right_ankle"})
    keypoints[j] = truth["body"]["canonical"][j];
  test::writeFile(dir / "keypoints.json", keypoints.dump());
  r = test::runCli("-q fit " + q(dir / "synth" / "scan.ply") + " --no-nonrigid --keypoints " +
                   q(dir / "keypoints.json") + " -o " + q(dir / "fit_kp"));
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json kp = readJson(dir / "fit_kp" / "body.json");
  EXPECT_EQ(kp["fit"]["initialisation"], "keypoints");
  double worst = 0;
  for (auto& [name, xyz] : kp["canonical"].items()) {
    const auto& t = truth["body"]["canonical"][name];
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += std::pow(xyz[k].get<double>() - t[k].get<double>(), 2);
    worst = std::max(worst, std::sqrt(d2));
  }
  EXPECT_LT(worst, 0.060);
}

TEST(FitCli, RefusesWhatIsNotAPersonWithoutWritingAnything) {
  test::TempDir dir;
  writePly(dir / "ball.ply", makeIcosphere(4, 0.9));
  for (const char* cmd : {"fit", "run"}) {
    const fs::path out = dir / (std::string(cmd) + "_ball");
    CliRun r = test::runCli(std::string("-q ") + cmd + " " + q(dir / "ball.ply") + " -o " + q(out));
    EXPECT_EQ(r.code, 5) << r.out;
    EXPECT_NE(r.out.find("not the main axis"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(out)) << cmd;
    r = test::runCli(std::string("-q ") + cmd + " " + q(dir / "missing.ply") + " -o " + q(out));
    EXPECT_EQ(r.code, 3) << r.out;
    EXPECT_FALSE(fs::exists(out)) << cmd;
  }
  const CliRun r =
      test::runCli("-q fit " + q(dir / "ball.ply") + " --model nosuchmodel -o " + q(dir / "m"));
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(fs::exists(dir / "m"));
}

}  // namespace
}  // namespace s2p
