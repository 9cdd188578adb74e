// `scan2pattern segment` end to end on a small synthetic scan: the outputs, their agreement with
// the truth through `eval`, and the refusals (no colour, a body elsewhere, bad arguments) that
// leave no output folder behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_support.h"
#include "io/read_ply.h"
#include "io/write_mesh.h"
#include "test_support.h"

namespace s2p {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::q;

// One small scan shared by the tests of this file.
const fs::path& synthScan() {
  static test::TempDir dir;
  static const bool made = [] {
    const CliRun r = test::runCli("-q synth --preset tshirt_trousers --seed 3 --vertices 9000 -o " +
                                  q(dir / "synth"));
    EXPECT_EQ(r.code, 0) << r.out;
    return r.code == 0;
  }();
  (void)made;
  static const fs::path path = dir / "synth";
  return path;
}

TEST(SegmentCli, SegmentsASyntheticScanAndEvalAgrees_Slow) {
  const fs::path synth = synthScan();
  test::TempDir out;
  const CliRun r = test::runCli("-q segment " + q(synth / "scan.ply") + " --truth " +
                                q(synth / "truth.json") + " -o " + q(out / "seg"));
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* name : {"segmentation.ply", "upper.obj", "lower.obj", "boundaries.json",
                           "garments.json", "segment_boundaries.png", "segment_labels.png"})
    EXPECT_TRUE(fs::exists(out / "seg" / name)) << name;
  // segmentation.ply keeps the scan's vertices and faces and adds the labels.
  const PlyData scan = readPly(synth / "scan.ply");
  const PlyData seg = readPly(out / "seg" / "segmentation.ply");
  EXPECT_EQ(seg.mesh.F, scan.mesh.F);
  EXPECT_LT((seg.mesh.V - scan.mesh.V).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(seg.faceLabels.size(), scan.mesh.numFaces());
  // Each garment face maps to a scan face of that garment's label, or (a face the cut crossed,
  // labelled by its larger side) to a face touching one; the trousers' hidden band (completed
  // under the t-shirt, §5.3) maps to faces the t-shirt shows.
  std::ifstream gin(out / "seg" / "garments.json");
  const nlohmann::json g = nlohmann::json::parse(gin);
  ASSERT_EQ(g["garments"].size(), 2u);
  std::vector<int> touches(seg.mesh.numVertices(), 0);  // bit per label of incident faces
  for (int f = 0; f < seg.mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) touches[seg.mesh.F(f, k)] |= 1 << seg.faceLabels[f];
  for (const auto& garment : g["garments"]) {
    const bool upper = garment["name"] == "upper";
    const int allowed = upper ? (1 << 1) : (1 << 1) | (1 << 2);
    int bad = 0;
    for (int f : garment["face_origin"]) {
      int near = 0;
      for (int k = 0; k < 3; ++k) near |= touches[seg.mesh.F(f, k)];
      bad += (near & allowed) == 0;
    }
    EXPECT_EQ(bad, 0) << garment["name"];
  }
  const CliRun e = test::runCli("-q eval --json --truth " + q(synth / "truth.json") + " --pred " +
                                    q(out / "seg"),
                                false);
  ASSERT_EQ(e.code, 0) << e.out;
  const nlohmann::json j = nlohmann::json::parse(e.out);
  EXPECT_GE(j["mean_garment_iou"].get<double>(), 0.97);
}

// A top and trousers of nearly one colour (low_contrast): colour cannot part them, the steps of
// the scan's offset from the body under the clothes can. `segment --truth` had no body under the
// clothes and took the outfit for one piece (garment IoU 0.245); the true body is that body.
TEST(SegmentCli, TheTrueBodyGivesTheGeometricCuesAsRunHasThem_Slow) {
  test::TempDir dir;
  const CliRun s = test::runCli("-q synth --preset low_contrast --seed 9 --vertices 14000 -o " +
                                q(dir / "synth"));
  ASSERT_EQ(s.code, 0) << s.out;
  const CliRun r = test::runCli("-q segment " + q(dir / "synth" / "scan.ply") + " --truth " +
                                q(dir / "synth" / "truth.json") + " -o " + q(dir / "seg"));
  ASSERT_EQ(r.code, 0) << r.out;
  const CliRun e = test::runCli("-q eval --json --truth " + q(dir / "synth" / "truth.json") +
                                    " --pred " + q(dir / "seg"),
                                false);
  ASSERT_EQ(e.code, 0) << e.out;
  const nlohmann::json j = nlohmann::json::parse(e.out);
  EXPECT_GE(j["mean_garment_iou"].get<double>(), 0.97);
}

// The MRF baseline with the same cues: a top of the wearer's own skin tone (skin_tone_top) is
// told from the bare arms and neck by its offset from the body under the clothes; by colour
// alone the graph cut gives much of it to the skin.
TEST(SegmentCli, TheMrfBaselineTakesTheOffsetIntoItsDataTerm_Slow) {
  test::TempDir dir;
  const CliRun s = test::runCli("-q synth --preset skin_tone_top --seed 3 --vertices 9000 -o " +
                                q(dir / "synth"));
  ASSERT_EQ(s.code, 0) << s.out;
  const auto upperIou = [&](const std::string& flags, const std::string& name) {
    const CliRun r = test::runCli("-q segment " + q(dir / "synth" / "scan.ply") + " --truth " +
                                  q(dir / "synth" / "truth.json") + " --segmenter mrf " + flags +
                                  " -o " + q(dir / name));
    EXPECT_EQ(r.code, 0) << r.out;
    const CliRun e = test::runCli("-q eval --json --truth " + q(dir / "synth" / "truth.json") +
                                      " --pred " + q(dir / name),
                                  false);
    EXPECT_EQ(e.code, 0) << e.out;
    return nlohmann::json::parse(e.out)["labels"]["upper"]["iou"].get<double>();
  };
  EXPECT_GE(upperIou("", "cues"), 0.97);             // 0.994 when written
  EXPECT_LT(upperIou("--colour-only", "colour"), 0.9);  // 0.852
}

TEST(SegmentCli, RefusesBadInputWithoutWritingAnything) {
  const fs::path synth = synthScan();
  test::TempDir dir;
  const std::string truth = " --truth " + q(synth / "truth.json");
  // Neither or both of --truth and --body: usage.
  EXPECT_EQ(test::runCli("segment " + q(synth / "scan.ply") + " -o " + q(dir / "a")).code, 2);
  EXPECT_EQ(test::runCli("segment " + q(synth / "scan.ply") + truth + " --body x.json -o " +
                         q(dir / "a"))
                .code,
            2);
  EXPECT_EQ(test::runCli("segment " + q(synth / "scan.ply") + truth +
                         " --segmenter nope -o " + q(dir / "a"))
                .code,
            2);
  // A scan without colour.
  const PlyData scan = readPly(synth / "scan.ply");
  writePly(dir / "grey.ply", scan.mesh);
  CliRun r = test::runCli("segment " + q(dir / "grey.ply") + truth + " -o " + q(dir / "b"));
  EXPECT_EQ(r.code, 5) << r.out;
  EXPECT_NE(r.out.find("colour"), std::string::npos) << r.out;
  // A body 10 m to the side of the scan.
  std::ifstream in(synth / "truth.json");
  nlohmann::json t = nlohmann::json::parse(in);
  t["body"]["translation"][0] = t["body"]["translation"][0].get<double>() + 10.0;
  test::writeFile(dir / "far.json", t["body"].dump());
  r = test::runCli("segment " + q(synth / "scan.ply") + " --body " + q(dir / "far.json") +
                   " -o " + q(dir / "c"));
  EXPECT_EQ(r.code, 5) << r.out;
  // A missing scan.
  EXPECT_EQ(test::runCli("segment " + q(dir / "none.ply") + truth + " -o " + q(dir / "d")).code, 3);
  for (const char* d : {"a", "b", "c", "d"}) EXPECT_FALSE(fs::exists(dir / d)) << d;
}

}  // namespace
}  // namespace s2p
