// `scan2pattern demo` ends with a pattern: every Patterns III file is written, GarmentCode's own
// loader (../shared/validators/gc_check.py) reads pattern.json with no error, every stitch's
// two sides are within 2 mm, stitches.json indexes panels.obj, and no placed panel comes within
// the clearance of the rest body. An unwritable output folder fails before any work. The demo
// runs without --drape here (drape_cli_test.cpp checks the drape).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.h"
#include "core/mesh_query.h"
#include "io/read_scan.h"
#include "test_support.h"

namespace s2p {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::objVertexCount;
using test::q;
using test::readJson;

class DemoPattern : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    run_ = new CliRun(test::runCli("-q demo -o " + q(dir_->path() / "demo")));
  }
  static void TearDownTestSuite() {
    delete run_;
    delete dir_;
  }
  static fs::path pattern() { return dir_->path() / "demo" / "pattern"; }
  static test::TempDir* dir_;
  static CliRun* run_;
};
test::TempDir* DemoPattern::dir_ = nullptr;
CliRun* DemoPattern::run_ = nullptr;

TEST_F(DemoPattern, WritesEveryPatternFile_Slow) {
  ASSERT_EQ(run_->code, 0) << run_->out;
  for (const char* f :
       {"pattern.json", "pattern.svg", "pattern.pdf", "pattern.dxf", "pattern.png", "panels.obj",
        "stitches.json", "body_rest.obj", "panels_flat.obj", "flat.json", "panels.json"})
    EXPECT_TRUE(fs::exists(pattern() / f) && fs::file_size(pattern() / f) > 0) << f;
  EXPECT_NE(run_->out.find("pattern.png"), std::string::npos) << "the demo names its picture";
  // No temporary file is left behind.
  for (const auto& e : fs::directory_iterator(pattern()))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  // The demo ends with the pattern sewn and draped (on by default, as the paper's Fig. 18 ends):
  // report.json's drape ran and settled, its stage is timed, drape/ holds the draped garments
  // and the comparison picture, and the demo names it (checked here: a test of its own would run
  // the demo once more under ctest).
  const nlohmann::json report = readJson(dir_->path() / "demo" / "report.json");
  EXPECT_TRUE(report.at("drape").at("ran").get<bool>());
  EXPECT_EQ(report.at("drape").at("status"), "settled") << report.at("drape").at("warnings");
  bool staged = false;
  for (const auto& s : report.at("stages")) staged = staged || s.at("stage") == "drape";
  EXPECT_TRUE(staged);
  EXPECT_TRUE(fs::exists(dir_->path() / "demo" / "drape" / "draped.obj"));
  EXPECT_TRUE(fs::exists(dir_->path() / "demo" / "drape" / "drape_compare.png"));
  EXPECT_NE(run_->out.find("drape_compare.png"), std::string::npos) << "the demo names its drape";
}

TEST_F(DemoPattern, StitchesPairPanelsObjVerticesAndTheirSidesAgree_Slow) {
  ASSERT_EQ(run_->code, 0) << run_->out;
  const nlohmann::json st = readJson(pattern() / "stitches.json");
  const int nV = objVertexCount(pattern() / "panels.obj");
  ASSERT_EQ(nV, objVertexCount(pattern() / "panels_flat.obj"));
  ASSERT_GT(st["stitches"].size(), 0u);
  for (const auto& s : st["stitches"]) {
    EXPECT_LT(s["mismatch_mm"].get<double>(), 2.0) << s["name"];
    for (const auto& pair : s["vertex_pairs"])
      for (int k = 0; k < 2; ++k) {
        EXPECT_GE(pair[k].get<int>(), 0);
        EXPECT_LT(pair[k].get<int>(), nV);
      }
  }
  const nlohmann::json report = readJson(dir_->path() / "demo" / "report.json");
  for (const auto& p : report["placement"]["panels"])
    EXPECT_GE(p["clearance_m"].get<double>(), 0.0199) << p["panel"] << " intersects the rest body";
  // The same, measured here independently of placement's own search: every vertex of
  // panels.obj outside body_rest.obj by its winding number and at least 2 cm from it.
  const Scan body = readScan(pattern() / "body_rest.obj", {.loadTexture = false});
  const Scan placed = readScan(pattern() / "panels.obj", {.loadTexture = false});
  const MeshQuery query(body.mesh);
  const Eigen::VectorXd winding = query.windingNumbers(placed.mesh.V);
  const std::vector<ClosestHit> hits = query.closestPoints(placed.mesh.V);
  int inside = 0;
  double least = 1e9;
  for (int v = 0; v < placed.mesh.numVertices(); ++v) {
    inside += winding(v) > 0.5;
    least = std::min(least, hits[v].distance);
  }
  EXPECT_EQ(inside, 0) << "placed vertices inside the rest body";
  EXPECT_GE(least, 0.0199) << "a placed vertex within 2 cm of the rest body";
}

TEST_F(DemoPattern, GarmentCodesOwnLoaderReadsThePattern_Slow) {
  ASSERT_EQ(run_->code, 0) << run_->out;
  const fs::path checker = test::sharedDir() / "validators" / "gc_check.py";
  if (test::sharedDir().empty() || !fs::exists(checker))
    GTEST_SKIP() << "../shared/validators/gc_check.py not found: GarmentCode's loader not run";
  if (!fs::exists("/usr/bin/python3"))
    GTEST_SKIP() << "/usr/bin/python3 not found: GarmentCode's loader not run";
  const fs::path report = dir_->path() / "gc.json";
  const std::string cmd = "/usr/bin/python3 " + q(checker) + " " + q(pattern() / "pattern.json") +
                          " " + q(dir_->path() / "gc") + " --no-images --strict --tol-cm 0.2" +
                          " --json " + q(report) + " 2>&1";
  std::string out;
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char buf[4096];
  while (fgets(buf, sizeof buf, pipe)) out += buf;
  const int status = pclose(pipe);
  ASSERT_EQ(WEXITSTATUS(status), 0) << out;
  const nlohmann::json r = readJson(report);
  EXPECT_TRUE(r["errors"].empty()) << r["errors"].dump();
  EXPECT_GT(r["n_stitches"].get<int>(), 0);
  EXPECT_LT(r["max_stitch_mismatch_cm"].get<double>(), 0.2);
  for (const auto& s : r["stitches"]) EXPECT_FALSE(s["probably_twisted"].get<bool>()) << s.dump();
}

TEST(PatternCli, AnUnwritableOutputFolderFailsBeforeAnyWork) {
  test::TempDir dir;
  {
    std::ofstream f(dir.path() / "file");
    f << "not a folder";
  }
  const fs::path scan = dir.path() / "scan.ply";
  ASSERT_EQ(
      test::runCli("-q synth --preset tshirt_trousers --vertices 3000 -o " + q(dir.path() / "s"))
          .code,
      0);
  const CliRun r = test::runCli("-q run " + q(dir.path() / "s" / "scan.ply") + " -o " +
                                q(dir.path() / "file" / "out"));
  EXPECT_EQ(r.code, 3) << r.out;  // ExitCode::Io
  EXPECT_NE(r.out.find("output folder"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("fit"), std::string::npos) << "no stage ran: " << r.out;
}

}  // namespace
}  // namespace s2p
