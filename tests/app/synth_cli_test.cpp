// `scan2pattern synth` and `bench-suite` end to end: the preset list, the exit code of an unknown
// preset, and a generated scan whose labels agree with its truth.json.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.h"
#include "io/read_ply.h"
#include "test_support.h"

namespace s2p {
namespace {

using test::CliRun;
using test::q;
CliRun run(const std::string& args) {
  return test::runCli(args);
}

int countLines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(SynthCli, ListsAtLeastFourteenPresets) {
  const CliRun r = run("-q synth --list");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_GE(countLines(r.out), 14);
  for (const char* name : {"tshirt_trousers", "dress", "jacket_layered", "low_contrast", "walking"})
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
}

TEST(SynthCli, UnknownPresetAndBadArgumentsGiveTheirExitCodes) {
  test::TempDir dir;
  const CliRun r = run("synth --preset nope -o " + q(dir / "out"));
  EXPECT_EQ(r.code, 5) << r.out;
  EXPECT_NE(r.out.find("nope"), std::string::npos);
  EXPECT_NE(r.out.find("tshirt_trousers"), std::string::npos);  // lists the known ones
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  EXPECT_EQ(run("synth --preset dress --format stl -o " + q(dir / "out")).code, 2);
  EXPECT_EQ(run("synth -o " + q(dir / "out")).code, 2);  // no preset
  EXPECT_EQ(run("synth --preset dress --vertices -3 -o " + q(dir / "out")).code, 2);
  EXPECT_EQ(run("bench-suite --suite " + q(dir / "missing.json") + " -o " + q(dir / "s")).code, 3);
  test::writeFile(dir / "bad.json", "{\"entries\": [{\"name\": \"x\", \"preset\": \"nope\"}]}");
  EXPECT_EQ(run("bench-suite --suite " + q(dir / "bad.json") + " -o " + q(dir / "s")).code, 4);
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(SynthCli, WritesScanAndTruthWhoseLabelsAgree_Slow) {
  test::TempDir dir;
  const CliRun r =
      run("-q synth --preset close_to_skin --seed 4 --vertices 8000 -o " + q(dir / "out"));
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* name : {"scan.ply", "truth.json", "preview_scan.png", "preview_labels.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / name)) << name;
  const PlyData ply = readPly(dir / "out" / "scan.ply");
  const auto truth = nlohmann::json::parse(test::readFile(dir / "out" / "truth.json"));
  ASSERT_EQ(ply.faceLabels.size(), ply.mesh.numFaces());
  EXPECT_EQ(truth["seed"].get<int>(), 4);
  EXPECT_EQ(truth["preset"].get<std::string>(), "close_to_skin");
  // Faces labelled Upper (1) in the PLY exactly when truth lists a visible upper garment.
  bool upperInTruth = false, lowerInTruth = false;
  for (const auto& g : truth["garments"]) {
    upperInTruth |= g["label"].get<std::string>() == "upper";
    lowerInTruth |= g["label"].get<std::string>() == "lower";
  }
  EXPECT_TRUE(upperInTruth);
  EXPECT_EQ((ply.faceLabels.array() == 1).any(), upperInTruth);
  EXPECT_EQ((ply.faceLabels.array() == 2).any(), lowerInTruth);
  // About the vertex count asked for (decimation target).
  EXPECT_GT(ply.mesh.numVertices(), 4000);
  EXPECT_LT(ply.mesh.numVertices(), 16000);
}

}  // namespace
}  // namespace s2p
