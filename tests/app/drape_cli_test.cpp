// `scan2pattern run --drape` sews and drapes its own pattern (issue 19): OUT/drape/draped.obj
// (every placed panel, on the rest body), drape_compare.png and report.json's "drape" figures
// against the scanned garment; a drape that cannot settle in its step budget is reported and never
// written, the pattern files written all the same. (Without --drape: pattern_cli_test's demo.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.h"
#include "test_support.h"

namespace s2p {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::objVertexCount;
using test::q;
using test::readJson;

bool anyContains(const nlohmann::json& warnings, const std::string& what) {
  for (const auto& w : warnings)
    if (w.get<std::string>().find(what) != std::string::npos) return true;
  return false;
}

// A small synthetic scan of `preset` in dir/synth/scan.ply.
fs::path synthScan(const fs::path& dir, const std::string& preset) {
  const CliRun s =
      test::runCli("-q synth --preset " + preset + " --vertices 9000 -o " + q(dir / "synth"));
  EXPECT_EQ(s.code, 0) << s.out;
  return dir / "synth" / "scan.ply";
}

// The drape's default options on a pattern remeshed at 30 mm: a sleeveless top and a knee-length
// skirt (the 10 mm demo pattern takes minutes on the shared machine; t-shirt and trousers at
// 30 mm sew and settle on the suite's scan, but the trousers' crotch does not close on this
// 9,000-vertex one: bench/RESULTS.md, Drape IV).
TEST(DrapeCli, RunDrapesThePatternAndMeasuresItAgainstTheScannedGarment_Slow) {
  test::TempDir dir;
  const fs::path scan = synthScan(dir.path(), "sleeveless_knee_skirt");
  const fs::path out = dir.path() / "run";
  const CliRun run = test::runCli("-q run --drape --remesh-edge 30 " + q(scan) + " -o " + q(out));
  ASSERT_EQ(run.code, 0) << run.out;
  const nlohmann::json report = readJson(out / "report.json");
  const nlohmann::json& d = report.at("drape");
  ASSERT_TRUE(d.at("ran").get<bool>()) << d.dump();
  EXPECT_EQ(d.at("status"), "settled") << d.dump();
  EXPECT_TRUE(d.at("written").get<bool>());
  EXPECT_TRUE(d.at("seams_closed").get<bool>());
  EXPECT_EQ(d.at("max_stitch_gap_mm").get<double>(), 0.0);  // sewn partners are one particle
  // GarmentCode's gates.
  EXPECT_LE(d.at("body_penetrations").get<int>(), 35);
  EXPECT_LE(d.at("self_intersections").get<int>(), 300);
  // Both garments measured both ways, and per panel.
  ASSERT_EQ(d.at("garments").size(), 2u) << d.dump();
  for (const auto& g : d.at("garments")) {
    for (const char* way : {"draped_to_scanned", "scanned_to_draped"}) {
      const double mean = g.at(way).at("mean_mm"), p95 = g.at(way).at("p95_mm");
      const double mx = g.at(way).at("max_mm");
      EXPECT_GT(mean, 0) << g.dump();
      EXPECT_LE(mean, p95) << g.dump();
      EXPECT_LE(p95, mx) << g.dump();
    }
    EXPECT_FALSE(g.at("panels_draped_to_scanned").empty());
  }
  // draped.obj: every placed panel's vertex, the same count as pattern/panels.obj.
  EXPECT_EQ(objVertexCount(out / "drape" / "draped.obj"),
            objVertexCount(out / "pattern" / "panels.obj"));
  EXPECT_TRUE(fs::exists(out / "drape" / "drape_compare.png"));
  EXPECT_NE(run.out.find("drape_compare.png"), std::string::npos) << "the run names its picture";
  bool staged = false;
  for (const auto& s : report.at("stages")) staged = staged || s.at("stage") == "drape";
  EXPECT_TRUE(staged) << "the drape's time is in the report's stages";
}

// A budget too small to sew the seams: reported in report.json, no draped.obj (an earlier run's
// drape is removed: it is not this pattern's) but the last state as unsettled.obj, every
// pattern file written.
TEST(DrapeCli, ADrapeThatDoesNotSettleInItsBudgetIsReportedAndNotWritten_Slow) {
  test::TempDir dir;
  const fs::path scan = synthScan(dir.path(), "tshirt_trousers");
  const fs::path again = dir.path() / "again";
  fs::create_directories(again / "drape");
  std::ofstream(again / "drape" / "draped.obj") << "# stale\n";
  const CliRun r = test::runCli("-q run --drape --remesh-edge 30 --drape-steps 3 " + q(scan) +
                                " -o " + q(again));
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json report = readJson(again / "report.json");
  const nlohmann::json& d = report.at("drape");
  EXPECT_TRUE(d.at("ran").get<bool>());
  EXPECT_EQ(d.at("status"), "not settled");
  EXPECT_FALSE(d.at("written").get<bool>());
  EXPECT_TRUE(d.at("garments").empty()) << "an unsettled cloth is not measured";
  EXPECT_TRUE(anyContains(report.at("warnings"), "the seams did not close")) << report["warnings"];
  EXPECT_TRUE(anyContains(report.at("warnings"), "no draped garment written"))
      << report["warnings"];
  EXPECT_FALSE(fs::exists(again / "drape" / "draped.obj"));
  EXPECT_FALSE(fs::exists(again / "drape" / "drape_compare.png"));
  // Its last state is left, named for what it is, to show where the seams stayed open.
  EXPECT_EQ(objVertexCount(again / "drape" / "unsettled.obj"), d.at("vertices").get<int>());
  for (const char* f : {"pattern.json", "pattern.svg", "panels.obj", "stitches.json"})
    EXPECT_TRUE(fs::exists(again / "pattern" / f)) << f;
}

}  // namespace
}  // namespace s2p
