// demo: the main job on a synthetic clothed scan of the built-in mannequin.
#include <fmt/format.h>

#include <memory>

#include "app/commands.h"
#include "app/drape_output.h"
#include "app/run_pipeline.h"
#include "body/body_source.h"
#include "eval/evaluation_files.h"
#include "synth/presets.h"
#include "synth/synthesize.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

// === demo: the main job on a synthetic clothed scan of the built-in mannequin, as far as the
// pipeline goes: generated with its ground truth, written, read back, cleaned, normalised,
// summarised, the body fitted, the garments segmented, and both scored against the truth.

constexpr const char* kDemoPreset = "tshirt_trousers";

int runDemo(const fs::path& outDir, bool withDrape, Progress& progress) {
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

  // From here on the truth is not used: the body is fitted and the garments segmented as
  // for any scan (`scan2pattern run`), then the result is scored against the truth.
  progress.begin("load body model mannequin");
  const BodyModel model = loadBodyModel("mannequin");
  progress.end();
  DrapeStageOptions drape;
  drape.enabled = withDrape;
  EarlyWriters early(outDir, loaded, model);
  const RunOutput run = runPipeline(loaded, model, {}, {}, progress, drape, {}, &early);
  writeRun(outDir, loaded, model, run, progress, {}, &early);
  printRun(run, outDir);
  const Evaluation e =
      evaluate(loadEvaluation(resolveEvaluationFiles(outDir / "truth.json", outDir / "segment", {},
                                                     outDir / "fit" / "body.json"))
                   .input());
  fmt::print("\n{}", formatEvaluation(e));
  fmt::print(
      "\nwrote {0}/: scan.ply (synthetic clothed scan, preset {1}, colours and labels), "
      "truth.json (garments, true boundaries, body), preview_scan.png and preview_labels.png "
      "(front, back), info.json, report.json;\n{0}/fit/: body_fit.obj, body_full.obj, body.json, "
      "fit_front.png, fit_side.png;\n{0}/segment/: segmentation.ply, upper.obj, lower.obj, "
      "boundaries.json, garments.json, segment_boundaries.png, segment_labels.png;\n{0}/pattern/: "
      "pattern.json (GarmentCode), pattern.pdf, pattern.svg (1:1), pattern.dxf (DXF-AAMA), "
      "panels.obj, stitches.json, body_rest.obj, flat.json, panels.json\n",
      outDir.string(), kDemoPreset);
  if (!run.patternError)
    fmt::print("the pattern: {}\n", (outDir / "pattern" / "pattern.png").string());
  // The demo ends as the paper's Fig. 18 does: the pattern sewn and draped.
  if (drapeWritten(run))
    fmt::print("the pattern sewn and draped: {}\n",
               (outDir / "drape" / "drape_compare.png").string());
  else if (withDrape)
    fmt::print("the drape: not written (see the warnings in {})\n",
               (outDir / "report.json").string());
  return 0;
}

}  // namespace

void addDemoCommand(CLI::App& app, Commands& out) {
  auto outDir = std::make_shared<std::string>("demo_out");
  auto withDrape = std::make_shared<bool>(true);
  auto* cmd = app.add_subcommand("demo",
                                 "Synthesise a clothed scan of the built-in mannequin (with truth "
                                 "and previews) and run the main job on it");
  cmd->add_option("-o,--output", *outDir, "Output folder")->capture_default_str();
  cmd->add_flag("--drape,!--no-drape", *withDrape,
                "Sew and drape the pattern and compare it with the scan (OUT/drape/): on by "
                "default, as the paper's Fig. 18 ends; --no-drape skips it");
  out.push_back({cmd, [outDir, withDrape](Progress& progress) {
                   return runDemo(*outDir, *withDrape, progress);
                 }});
}

}  // namespace s2p::app
