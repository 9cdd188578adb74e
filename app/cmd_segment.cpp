// segment: garment segmentation of a scan with a known posed body (paper §5).
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <memory>

#include "app/commands.h"
#include "app/segment_output.h"
#include "body/body_json.h"
#include "body/body_source.h"
#include "core/error.h"
#include "eval/boundary_metrics.h"
#include "eval/evaluation_files.h"
#include "io/write_mesh.h"
#include "synth/truth.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

struct SegmentCommand {
  std::string scan;
  std::string truth;
  std::string body;
  std::string out = "segment_out";
  std::string segmenter = "curve";
  bool faithful = false;
  bool noGapFilling = false;
  bool colourOnly = false;
  int coarseVertices = SegmentationOptions{}.coarseVertices;
  LoadOptions load;
};

json truthBody(const fs::path& truth) {
  const json t = readJsonFile(truth, "truth file");
  if (!t.contains("body") || !t["body"].is_object())
    throw FormatError(fmt::format("truth file {} has no \"body\" object", truth.string()));
  return t["body"];
}

// underBody: the body under the clothes (underBodyForScan), for the geometric cues as `run` has
// them.
SegmentOutput runSegmenter(const std::string& segmenter, const Scan& scan,
                           const PosedFeatures& body, const TriMesh& underBody,
                           const SegmentationOptions& options, Progress& progress) {
  if (segmenter == "mrf")
    return segmentWithMrf(scan, body.body, underBody, body.features, options, progress);
  return {
      segmentScan(scan.mesh, scan.colour, body.body, underBody, body.features, options, &progress),
      "curve"};
}

void checkSegmenter(const std::string& segmenter) {
  if (segmenter != "curve" && segmenter != "mrf")
    throw CLI::ValidationError("--segmenter", "use curve (the paper's method) or mrf");
}

SegmentationOptions segmentationOptions(bool faithful, bool noGapFilling, int coarseVertices,
                                        bool colourOnly) {
  SegmentationOptions options;
  options.boundary.faithful = faithful;
  options.gapFilling = !noGapFilling;
  options.geometry.enabled = !colourOnly;
  options.coarseVertices = coarseVertices;
  return options;
}

// --colour-only: the paper's displacement, without issue 18's geometric cues.
void addColourOnlyFlag(CLI::App* cmd, bool& colourOnly) {
  cmd->add_flag("--colour-only", colourOnly,
                "Colour alone decides, as in the paper: no geometric cues (the scan's offset from "
                "the body under the clothes and its steps at hems), for either segmenter");
}

// --coarse-vertices: 0, or enough vertices for a person (core/coarse_mesh.h).
void addCoarseOption(CLI::App* cmd, int& coarseVertices) {
  cmd->add_option("--coarse-vertices", coarseVertices,
                  "Optimise the boundaries of a scan with more than 1.5x this many vertices on a "
                  "decimated copy of about this many, then cut the full scan exactly along them; "
                  "0: at full resolution")
      ->check(CLI::Range(0, 0) | CLI::Range(1000, 100000000))
      ->capture_default_str();
}

int runSegment(const SegmentCommand& cmd, Progress& progress) {
  if (cmd.truth.empty() == cmd.body.empty())
    throw CLI::ValidationError("--truth/--body", "give exactly one of --truth and --body");
  checkSegmenter(cmd.segmenter);
  const json bodyJson =
      cmd.truth.empty() ? readJsonFile(cmd.body, "body file") : truthBody(cmd.truth);
  const LoadedScan loaded = loadScan(cmd.scan, cmd.load, progress);
  const fs::path bodyDir = cmd.body.empty() ? fs::path() : fs::absolute(cmd.body).parent_path();
  const PosedFeatures body = poseBodyForScan(bodyJson, loaded.scan, progress, bodyDir);
  const SegmentOutput result = runSegmenter(
      cmd.segmenter, loaded.scan, body, underBodyForScan(bodyJson, body, loaded.scan, bodyDir),
      segmentationOptions(cmd.faithful, cmd.noGapFilling, cmd.coarseVertices, cmd.colourOnly),
      progress);
  progress.begin("write outputs");
  writeSegmentation(cmd.out, loaded.scan, result);
  progress.end();
  printSegmentation(result.segmentation);
  fmt::print(
      "wrote {}/: segmentation.ply, {}{}, garments.json, segment_boundaries.png, "
      "segment_labels.png\n",
      cmd.out, garmentFileList(result.segmentation),
      result.segmenter == "mrf" ? "segment_report.json" : "boundaries.json");
  return 0;
}

// === segment-suite: every scan of a bench-suite folder, segmented with its true body and scored.

struct SuiteCommand {
  std::string suiteDir;
  std::string out = "segment_suite_out";
  std::string segmenter = "curve";
  std::string only;
  std::string reference;  // an earlier segment-suite output to compare boundaries with
  bool faithful = false;
  bool noGapFilling = false;
  bool colourOnly = false;
  int coarseVertices = SegmentationOptions{}.coarseVertices;
};

// Mean and worst p95 distance (m) between this run's boundary curves and a reference run's,
// over the label pairs both have (compareBoundary, both directions pooled).
std::pair<double, double> boundaryDifference(const fs::path& ours, const fs::path& reference) {
  const std::vector<TrueBoundary> a = readBoundaries(ours), b = readBoundaries(reference);
  double sum = 0, worst = 0;
  int n = 0;
  for (const TrueBoundary& ref : b)
    for (const TrueBoundary& x : a)
      if (x.a == ref.a && x.b == ref.b) {
        const BoundaryScore sc = compareBoundary(ref, &x);
        if (sc.missing) continue;
        sum += sc.pooled.mean;
        worst = std::max(worst, sc.pooled.p95);
        ++n;
      }
  return {n ? sum / n : 0.0, worst};
}

int runSegmentSuite(const SuiteCommand& cmd, Progress& progress) {
  checkSegmenter(cmd.segmenter);
  const std::vector<fs::path> truths = suiteTruths(cmd.suiteDir, cmd.only);
  const SegmentationOptions options =
      segmentationOptions(cmd.faithful, cmd.noGapFilling, cmd.coarseVertices, cmd.colourOnly);
  json rows = json::array();
  std::string table =
      "| preset | layout | occlusion | garment IoU | boundary mean mm | worst p95 mm | worst "
      "roughness | missing | seconds |" +
      std::string(cmd.reference.empty() ? "" : " vs reference mean / p95 mm |") + "\n" +
      "|---|---|---|---|---|---|---|---|---|" + (cmd.reference.empty() ? "" : "---|") + "\n";
  for (const fs::path& truthPath : truths) {
    const std::string name = truthPath.parent_path().filename().string();
    progress.message(fmt::format("suite entry {}", name));
    const Truth truth = readTruth(truthPath);
    const fs::path scanPath = truthPath.parent_path() / truth.scanFile;
    const fs::path outDir = fs::path(cmd.out) / name;
    json row = {{"preset", name}};
    try {
      const LoadedScan loaded = loadScan(scanPath, {}, progress);
      const PosedFeatures body = poseBodyForScan(truth.body, loaded.scan, progress);
      const SegmentOutput result =
          runSegmenter(cmd.segmenter, loaded.scan, body, body.body, options, progress);
      writeSegmentation(outDir, loaded.scan, result);
      const SegmentScore score = scoreSegmentation(truthPath, outDir);
      const Evaluation& e = score.evaluation;
      const Segmentation& s = result.segmentation;
      const bool mrf = cmd.segmenter == "mrf";  // no layout or occlusion decisions
      row.update({{"layout", toString(s.layout)},
                  {"occlusion", toString(s.occlusion)},
                  {"garment_iou", e.meanGarmentIoU},
                  {"boundary_mean_mm", 1000 * score.boundaryMean},
                  {"worst_p95_mm", 1000 * score.worstP95},
                  {"worst_roughness", score.worstRoughness},
                  {"missing", score.missing},
                  {"seconds", s.seconds},
                  {"evaluation", evaluationToJson(e)}});
      table +=
          fmt::format("| {} | {} | {} | {:.3f} | {:.2f} | {:.2f} | {:.3f} | {} | {:.1f} |", name,
                      mrf ? "-" : toString(s.layout), mrf ? "-" : toString(s.occlusion),
                      e.meanGarmentIoU, 1000 * score.boundaryMean, 1000 * score.worstP95,
                      score.worstRoughness, score.missing.empty() ? "-" : score.missing, s.seconds);
      const fs::path refBoundaries = fs::path(cmd.reference) / name / "boundaries.json";
      if (!cmd.reference.empty() && fs::exists(refBoundaries) &&
          fs::exists(outDir / "boundaries.json")) {
        const auto [mean, p95] = boundaryDifference(outDir / "boundaries.json", refBoundaries);
        row["vs_reference_mean_mm"] = 1000 * mean;
        row["vs_reference_p95_mm"] = 1000 * p95;
        table += fmt::format(" {:.2f} / {:.2f} |", 1000 * mean, 1000 * p95);
      } else if (!cmd.reference.empty()) {
        table += " - |";
      }
      table += "\n";
    } catch (const Error& err) {
      row["error"] = err.what();
      table += fmt::format("| {} | error: {} |||||||\n", name, err.what());
    }
    rows.push_back(row);
  }
  fs::create_directories(cmd.out);
  writeJson(fs::path(cmd.out) / "segment_suite.json",
            {{"segmenter", cmd.segmenter}, {"faithful", cmd.faithful}, {"rows", rows}});
  writeFileAtomically(fs::path(cmd.out) / "segment_suite.md", table);
  fmt::print("{}", table);
  return 0;
}

}  // namespace

void addSegmentCommand(CLI::App& app, Commands& out) {
  auto o = std::make_shared<SegmentCommand>();
  auto* cmd = app.add_subcommand(
      "segment",
      "Segment the garments of a scan (paper §5): the boundaries upper|skin, lower|skin-or-"
      "shoes and upper|lower, found by boundary optimisation from a posed body's feature points");
  cmd->add_option("SCAN", o->scan, "Scan file (PLY or OBJ with colour)")->required();
  cmd->add_option("--truth", o->truth, "truth.json of a synthetic scan: use its true body");
  cmd->add_option("--body", o->body, "body.json of a fitted or made body (scan2pattern body)");
  cmd->add_option("-o,--output", o->out, "Output folder")->capture_default_str();
  cmd->add_option("--segmenter", o->segmenter,
                  "curve: boundary optimisation (the paper); mrf: per-vertex graph-cut labelling "
                  "(the paper's Fig. 14 baseline)")
      ->capture_default_str();
  cmd->add_flag("--faithful", o->faithful,
                "Algorithm 1 as written: the biharmonic and the signed distance recomputed every "
                "iteration (3-4x slower; the default fast path, signed distance from the "
                "regularised isoline, reaches the same boundaries on the benchmark suite)");
  cmd->add_flag("--no-gap-filling", o->noGapFilling,
                "Skip the second pass for gap-filling triangles (§5.2)");
  addColourOnlyFlag(cmd, o->colourOnly);
  addCoarseOption(cmd, o->coarseVertices);
  addLoadOptions(cmd, o->load);
  out.push_back({cmd, [o](Progress& progress) { return runSegment(*o, progress); }});

  auto so = std::make_shared<SuiteCommand>();
  auto* suite = app.add_subcommand(
      "segment-suite",
      "Segment every scan of a bench-suite folder with its true body, score each against its "
      "truth.json and print the table (segment_suite.md, segment_suite.json)");
  suite->add_option("DIR", so->suiteDir, "Folder written by scan2pattern bench-suite")->required();
  suite->add_option("-o,--output", so->out, "Output folder")->capture_default_str();
  suite->add_option("--segmenter", so->segmenter, "curve or mrf")->capture_default_str();
  suite->add_option("--only", so->only, "Run only the entry of this name");
  suite->add_flag("--faithful", so->faithful, "Algorithm 1 as written (see segment --faithful)");
  suite->add_option("--reference", so->reference,
                    "An earlier segment-suite output: adds the distance between its boundaries "
                    "and this run's (e.g. faithful path against fast)");
  suite->add_flag("--no-gap-filling", so->noGapFilling, "Skip the gap-filling pass (§5.2)");
  addColourOnlyFlag(suite, so->colourOnly);
  addCoarseOption(suite, so->coarseVertices);
  out.push_back({suite, [so](Progress& progress) { return runSegmentSuite(*so, progress); }});
}

}  // namespace s2p::app
