// demo: the main job on a synthetic clothed scan of the built-in mannequin.
#include <fmt/format.h>

#include <memory>

#include "app/commands.h"
#include "app/segment_output.h"
#include "eval/evaluation_files.h"
#include "synth/presets.h"
#include "synth/synthesize.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

// === demo: the main job on a synthetic clothed scan of the built-in mannequin, as far as the
// pipeline goes: generated with its ground truth, written, read back, cleaned, normalised,
// summarised, segmented with its true body (the body fit comes next) and scored.

constexpr const char* kDemoPreset = "tshirt_trousers";

int runDemo(const fs::path& outDir, Progress& progress) {
  SynthOptions options = presetOptions(kDemoPreset);
  options.bodySource = "mannequin";
  const SynthScan synth = synthesize(options, progress);
  progress.begin("write synthetic scan, truth and previews");
  writeSynthScan(outDir, synth, SynthFormat::Ply);
  progress.end();
  LoadedScan loaded = loadScan(outDir / "scan.ply", {}, progress);
  const json info = infoJson(loaded);
  printInfo(info);
  writeJson(outDir / "info.json", info);

  const PosedFeatures body = poseBodyForScan(synth.truth.body, loaded.scan, progress);
  const SegmentOutput seg{segmentScan(loaded.scan.mesh, loaded.scan.colour, body.body,
                                      body.features, {}, &progress),
                          "curve"};
  progress.begin("write segmentation");
  writeSegmentation(outDir / "segment", loaded.scan, seg);
  progress.end();
  printSegmentation(seg.segmentation);
  const Evaluation e = evaluate(loadEvaluation(resolveEvaluationFiles(outDir / "truth.json",
                                                                      outDir / "segment"))
                                    .input());
  fmt::print("\n{}", formatEvaluation(e));
  fmt::print(
      "\nwrote {}/: scan.ply (synthetic clothed scan, preset {}, colours and labels), truth.json "
      "(garments, true boundaries, body), preview_scan.png and preview_labels.png (front, back), "
      "info.json;\n{}/segment/: segmentation.ply, upper.obj, lower.obj, boundaries.json, "
      "garments.json, segment_boundaries.png, segment_labels.png\n",
      outDir.string(), kDemoPreset, outDir.string());
  return 0;
}

}  // namespace

void addDemoCommand(CLI::App& app, Commands& out) {
  auto outDir = std::make_shared<std::string>("demo_out");
  auto* cmd = app.add_subcommand("demo",
                                 "Synthesise a clothed scan of the built-in mannequin (with truth "
                                 "and previews) and run the main job on it");
  cmd->add_option("-o,--output", *outDir, "Output folder")->capture_default_str();
  out.push_back({cmd, [outDir](Progress& progress) { return runDemo(*outDir, progress); }});
}

}  // namespace s2p::app
