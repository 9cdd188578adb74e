// fit: the body under the clothes (paper §4, App. A, §5.1.2); run: fit, then segment, on a scan
// nobody labelled; fit-suite: the fit (and optionally the whole run) over a bench-suite folder,
// scored against the truth.
#include <fmt/format.h>

#include <algorithm>
#include <future>
#include <memory>
#include <sstream>

#include "app/commands.h"
#include "app/drape_output.h"
#include "app/fit_output.h"
#include "app/pattern_files.h"
#include "app/pattern_output.h"
#include "app/run_pipeline.h"
#include "app/segment_output.h"
#include "body/body_json.h"
#include "body/body_source.h"
#include "core/error.h"
#include "eval/pattern_metrics.h"
#include "fit/keypoints.h"
#include "fit/scan_fit.h"
#include "io/write_mesh.h"
#include "synth/truth.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

struct FitCommand {
  std::string scan;
  std::string out;
  std::string model = "mannequin";
  std::string keypoints;
  bool noNonrigid = false;
  bool singleStart = false;
  LoadOptions load;
};

void addFitOptions(CLI::App* cmd, FitCommand& o) {
  cmd->add_option("SCAN", o.scan, "Scan file (PLY, OBJ, glTF)")->required();
  cmd->add_option("-o,--output", o.out, "Output folder")->capture_default_str();
  cmd->add_option("--model", o.model,
                  "Body model: mannequin (built in), mpfb2:DIR (MakeHuman/MPFB2 folder) or "
                  "smpl:FILE.npz")
      ->capture_default_str();
  cmd->add_option("--keypoints", o.keypoints,
                  "3D joints instead of the geometric pose initialisation, in the scan file's "
                  "frame: OpenPose BODY_25 --3d output (see render-views), or a map "
                  "{\"left_wrist\": [x, y, z], ...} of canonical joint names");
  cmd->add_flag("--no-nonrigid", o.noNonrigid,
                "Skip the non-rigid full fit (body_full.obj is then the fitted body)");
  cmd->add_flag("--single-start", o.singleStart,
                "Fit from the geometric pose initialisation alone (the rest pose when it fails) "
                "instead of the best of several starts (geometry, arms down, rest): faster, "
                "loses arms that hang against the thighs");
  addLoadOptions(cmd, o.load);
}

BodyModel loadModel(const std::string& spec, Progress& progress) {
  progress.begin("load body model " + spec);
  BodyModel m = loadBodyModel(spec);
  progress.end();
  return m;
}

// The scan and the body model, the model built while the scan is read and cleaned: neither
// needs the other (the mannequin takes 0.7 s to build, a 50k scan 0.3 s to read and clean).
// The progress line of the model shows what is left to wait for once the scan is in.
struct ScanAndModel {
  LoadedScan scan;
  BodyModel model;
};
ScanAndModel loadScanAndModel(const fs::path& scanPath, const LoadOptions& load,
                              const std::string& spec, Progress& progress) {
  // A std::async future waits for its task when destroyed, also when loadScan throws.
  std::future<BodyModel> model =
      std::async(std::launch::async, [spec] { return loadBodyModel(spec); });
  ScanAndModel out{loadScan(scanPath, load, progress), {}};
  progress.begin("load body model " + spec);
  out.model = model.get();
  progress.end();
  return out;
}

ScanFitOptions scanFitOptions(const FitCommand& cmd, const Scan& scan) {
  ScanFitOptions o;
  o.nonrigid = !cmd.noNonrigid;
  o.multiStart = !cmd.singleStart;
  if (!cmd.keypoints.empty())
    o.keypoints = readKeypoints(cmd.keypoints, scan.toInputFrame.inverse());
  return o;
}

int runFit(const FitCommand& cmd, Progress& progress) {
  const auto [loaded, model] = loadScanAndModel(cmd.scan, cmd.load, cmd.model, progress);
  const ScanFit fit = fitScan(loaded.scan.mesh, model, scanFitOptions(cmd, loaded.scan), &progress);
  progress.begin("write outputs");
  writeFit(cmd.out, loaded.scan, model, fit);
  progress.end();
  printFit(fit);
  fmt::print("wrote {}/: body_fit.obj, body_full.obj, body.json, fit_front.png, fit_side.png\n",
             cmd.out);
  return 0;
}

// === run: fit, then segment; report.json.

struct RunCommand {
  FitCommand fit;
  bool faithful = false;
  bool drape = true;         // the drape check after the pattern (--no-drape: skipped)
  int drapeSteps = -1;       // step budget of each drape phase; −1: DrapeOptions' defaults
  double drapeCoarseEdgeMm = 1000 * DrapeStageOptions{}.coarseEdge;  // 0: one level only
  double remeshEdgeMm = 10;  // the panels' remeshing target edge
  PrintOptions print;
  PatternOptions pattern;
};

int runRun(const RunCommand& cmd, Progress& progress) {
  requireWritableFolder(cmd.fit.out);
  const auto [loaded, model] =
      loadScanAndModel(cmd.fit.scan, cmd.fit.load, cmd.fit.model, progress);
  SegmentationOptions so;
  so.boundary.faithful = cmd.faithful;
  DrapeStageOptions drape;
  drape.enabled = cmd.drape;
  if (cmd.drapeSteps >= 0) drape.drape.sewMaxSteps = drape.drape.drapeMaxSteps = cmd.drapeSteps;
  drape.coarseEdge = cmd.drapeCoarseEdgeMm / 1000;
  PatternOptions pattern = cmd.pattern;
  pattern.flat.remesh.targetEdgeLength = cmd.remeshEdgeMm / 1000;
  EarlyWriters early(cmd.fit.out, loaded, model);  // fit/ and segment/ written as they are done
  const RunOutput run = runPipeline(loaded, model, scanFitOptions(cmd.fit, loaded.scan), so,
                                    progress, drape, pattern, &early);
  writeRun(cmd.fit.out, loaded, model, run, progress, cmd.print, &early);
  printRun(run, cmd.fit.out);
  if (run.patternError) std::rethrow_exception(run.patternError);
  return 0;
}

// === fit-suite

// The pattern columns of a fit-suite row (and its pattern/ folder): garment types and panel sets
// against the truth, and where the seams landed.
std::string patternColumns(const RunOutput& run, const Truth& truth, const Scan& scan,
                           const fs::path& outDir, json& row) {
  if (run.patternError) {
    row["pattern_error"] = run.patternErrorMessage;
    return fmt::format(" pattern error: {} |||||||", run.patternErrorMessage);
  }
  writePanels(outDir / "pattern", scan, run.pattern.panels);
  try {
    writeFlatPattern(outDir / "pattern", scan, run.pattern.panels, run.pattern.flat);
    writePatternFiles(outDir / "pattern", scan, run.pattern, {});
    row["placement"] = placementToJson(run.pattern);
  } catch (const Error& e) {
    row["pattern_files_error"] = e.what();
  }
  const PatternScore ps = scorePattern(run.pattern.panels, truth, run.fit.fittedInScanFrame(),
                                       run.fit.canonicalInScanFrame());
  std::string types, sets;
  json garments = json::array();
  for (const GarmentPatternScore& g : ps.garments) {
    types += fmt::format("{}{}{}", types.empty() ? "" : ", ",
                         g.foundType.empty() ? "none" : g.foundType, g.typeOk ? "" : " ✗");
    sets += fmt::format("{}{}/{}{}", sets.empty() ? "" : ", ", g.foundPanels.size(),
                        g.expectedPanels.size(), g.panelsOk ? "" : " ✗");
    garments.push_back({{"truth", g.truthGarment},
                        {"expected_type", g.expectedType},
                        {"found_type", g.foundType},
                        {"expected_panels", g.expectedPanels},
                        {"found_panels", g.foundPanels},
                        {"type_ok", g.typeOk},
                        {"panels_ok", g.panelsOk}});
  }
  double seconds = 0;
  for (const auto& [stage, t] : run.stages)
    if (stage == "panels") seconds = t;
  row["pattern"] = {{"garments", garments},
                    {"types_ok", ps.allTypesOk},
                    {"panels_ok", ps.allPanelsOk},
                    {"panels", ps.panels},
                    {"disks", ps.disks},
                    {"seam_edges", ps.seamEdges},
                    {"unpartnered", ps.unpartnered},
                    {"max_partner_mismatch", ps.maxPartnerMismatch},
                    {"seconds", seconds}};
  row["pattern"].update(patternScoreFigures(ps));
  const auto maxOr = [](bool any, double v, const char* fmtStr) {
    return any ? fmt::format(fmt::runtime(fmtStr), v) : std::string("–");
  };
  double worstArmhole = 0;
  for (const auto& [n, d] : ps.armholeToArmpit)
    if (std::abs(d) > std::abs(worstArmhole)) worstArmhole = d;
  return fmt::format(" {} | {} | {}/{} | {} | {} | {} | {:.2f} |", types, sets, ps.disks, ps.panels,
                     maxOr(!ps.armholeToArmpit.empty(), 1000 * worstArmhole, "{:+.0f}"),
                     maxOr(!ps.mirrorAreaDiff.empty(), 100 * ps.maxMirrorAreaDiff(), "{:.1f}") +
                         (ps.mirrorClothAreaDiff.empty()
                              ? ""
                              : fmt::format(" ({:.1f})", 100 * ps.maxMirrorClothAreaDiff())),
                     maxOr(!ps.sideSeamAngle.empty(), ps.maxSideSeamAngle(), "{:.0f}") +
                         (ps.sideSeamLimbAngle.empty()
                              ? ""
                              : fmt::format(" ({:.0f})", ps.maxSideSeamLimbAngle())),
                     seconds);
}

struct FitSuiteCommand {
  std::string suiteDir;
  std::string out = "fit_suite_out";
  std::string model = "mannequin";
  std::string only;
  std::vector<double> rotations{0};
  bool segment = false;
  bool faithful = false;
  bool noNonrigid = false;
  bool singleStart = false;
  bool drape = false;  // with segment: also sew and drape each pattern (issue 19's suite check)
};

// The drape columns of a fit-suite row: status, per garment draped-vs-scanned mean / p95 mm and
// how far its top hangs below the scanned top (mm), self-intersections and penetrations
// (GarmentCode's gates), seconds; the figures into row.
std::string drapeColumns(const RunOutput& run, const fs::path& outDir, json& row) {
  writeDrape(outDir / "drape", run);
  row["drape"] = drapeToJson(run);
  const DrapeStage& d = run.drape;
  if (!d.ran) return " not run |||||";
  std::string garments;
  for (const GarmentDrape& g : d.garments)
    if (g.draped.numFaces() > 0)
      garments += fmt::format("{}{} {:.1f} / {:.1f} ({:.0f})", garments.empty() ? "" : ", ",
                              g.garment, g.comparison.meanMm(), g.comparison.p95Mm(),
                              g.topDropMm);
  const DrapeResult& r = d.drape;
  return fmt::format(" {} | {} | {} | {} | {:.1f} |", toString(r.status),
                     garments.empty() ? "–" : garments, r.selfIntersections, r.bodyPenetrations,
                     d.seconds);
}

Eigen::MatrixX3d applied(const Eigen::Affine3d& T, const Eigen::MatrixX3d& P) {
  return (P * T.linear().transpose()).rowwise() + T.translation().transpose();
}

int runFitSuite(const FitSuiteCommand& cmd, Progress& progress) {
  const std::vector<fs::path> truths = suiteTruths(cmd.suiteDir, cmd.only);
  const BodyModel model = loadModel(cmd.model, progress);

  json rows = json::array();
  std::string table = fmt::format(
      "| preset | rotation ° | joint mean mm | joint max mm (joint) | inside or ≤5 mm % | yaw "
      "error ° | fit s |{}{}\n|---|---|---|---|---|---|---|{}{}\n",
      cmd.segment ? " garment IoU | boundary mean mm | worst p95 mm | types | panel sets | disks | "
                    "armhole − armpit mm | mirror area % (cloth) | side seam ° (limb's plane) | "
                    "panels s |"
                  : "",
      cmd.segment && cmd.drape ? " drape | draped vs scanned mean / p95 mm (top drop mm) | self-isect | "
                                 "penetrations | drape s |"
                               : "",
      cmd.segment ? "---|---|---|---|---|---|---|---|---|---|" : "",
      cmd.segment && cmd.drape ? "---|---|---|---|---|" : "");
  for (const fs::path& truthPath : truths) {
    const std::string name = truthPath.parent_path().filename().string();
    const Truth truth = readTruth(truthPath);
    for (const double rotation : cmd.rotations) {
      progress.message(fmt::format("suite entry {} rotated {}°", name, rotation));
      json row = {{"preset", name}, {"rotation_degrees", rotation}};
      try {
        LoadedScan loaded = loadScan(truthPath.parent_path() / truth.scanFile, {}, progress);
        const Eigen::Affine3d turn = turnAboutVertical(loaded.scan.mesh, rotation * M_PI / 180);
        loaded.scan.mesh.V = applied(turn, loaded.scan.mesh.V);
        loaded.scan.toInputFrame = loaded.scan.toInputFrame * turn.inverse();
        const BodyFromJson trueBody = bodyFromJson(truth.body);
        const Eigen::MatrixX3d trueCanonical =
            applied(loaded.scan.toInputFrame.inverse(), trueBody.posed.canonical);
        SegmentationOptions so;
        so.boundary.faithful = cmd.faithful;
        ScanFitOptions fo;
        fo.nonrigid = !cmd.noNonrigid;
        fo.multiStart = !cmd.singleStart;
        RunOutput run;
        DrapeStageOptions drape;
        drape.enabled = cmd.drape;  // by default the fit, segmentation and pattern only
        if (cmd.segment)
          run = runPipeline(loaded, model, fo, so, progress, drape);
        else
          run.fit = fitScan(loaded.scan.mesh, model, fo, &progress);
        const ScanFit& fit = run.fit;
        const Eigen::MatrixX3d canonical = fit.canonicalInScanFrame();
        double sum = 0, worst = 0;
        int worstJoint = 0;
        for (int c = 0; c < kNumCanonical; ++c) {
          const double e = (canonical.row(c) - trueCanonical.row(c)).norm();
          sum += e;
          if (e > worst) worst = e, worstJoint = c;
        }
        // The yaw that should have been found: the truth faces +Z in the file's frame.
        double yawError = std::remainder(fit.orientation.yaw + rotation * M_PI / 180, 2 * M_PI);
        yawError = std::abs(yawError) * 180 / M_PI;
        row.update({{"joint_mean_mm", 1000 * sum / kNumCanonical},
                    {"joint_max_mm", 1000 * worst},
                    {"worst_joint", toString(static_cast<Canonical>(worstJoint))},
                    {"inside_or_within_5mm", fit.fit.insideOrNear},
                    {"yaw_error_degrees", yawError},
                    {"initialisation", fit.initialisation},
                    {"start", fitStartJson(fit)},
                    {"fit_seconds", fit.seconds},
                    {"warnings", fit.warnings}});
        std::string line = fmt::format(
            "| {} | {:.0f} | {:.1f} | {:.1f} ({}) | {:.1f} | {:.1f} | {:.1f} |", name, rotation,
            1000 * sum / kNumCanonical, 1000 * worst, toString(static_cast<Canonical>(worstJoint)),
            100 * fit.fit.insideOrNear, yawError, fit.seconds);
        const fs::path outDir = fs::path(cmd.out) / fmt::format("{}_{:.0f}", name, rotation);
        writeFit(outDir / "fit", loaded.scan, model, fit);
        if (cmd.segment) {
          const SegmentOutput& seg = run.segment;
          writeSegmentation(outDir / "segment", loaded.scan, seg);
          const SegmentScore score = scoreSegmentation(truthPath, outDir / "segment");
          row.update({{"garment_iou", score.evaluation.meanGarmentIoU},
                      {"boundary_mean_mm", 1000 * score.boundaryMean},
                      {"worst_p95_mm", 1000 * score.worstP95},
                      {"layout", toString(seg.segmentation.layout)}});
          line += fmt::format(" {:.3f} | {:.2f} | {:.2f} |", score.evaluation.meanGarmentIoU,
                              1000 * score.boundaryMean, 1000 * score.worstP95);
          line += patternColumns(run, truth, loaded.scan, outDir, row);
          if (cmd.drape) line += drapeColumns(run, outDir, row);
        }
        table += line + "\n";
      } catch (const Error& err) {
        row["error"] = err.what();
        table += fmt::format("| {} | {:.0f} | error: {} ||||||\n", name, rotation, err.what());
      }
      rows.push_back(row);
    }
  }
  fs::create_directories(cmd.out);
  writeJson(fs::path(cmd.out) / "fit_suite.json",
            {{"model", model.source}, {"segment", cmd.segment}, {"rows", rows}});
  writeFileAtomically(fs::path(cmd.out) / "fit_suite.md", table);
  fmt::print("{}", table);
  return 0;
}

}  // namespace

void addFitCommands(CLI::App& app, Commands& out) {
  auto o = std::make_shared<FitCommand>();
  o->out = "fit_out";
  auto* cmd = app.add_subcommand(
      "fit",
      "Fit the body model under the clothes of a scan (paper §4, App. A): facing direction, pose "
      "initialisation from the scan's extremities, shape and pose by Levenberg-Marquardt keeping "
      "the body inside the scan, then a non-rigid fit onto the scan surface (§5.1.2)");
  addFitOptions(cmd, *o);
  out.push_back({cmd, [o](Progress& progress) { return runFit(*o, progress); }});

  auto r = std::make_shared<RunCommand>();
  r->fit.out = "run_out";
  auto* run = app.add_subcommand(
      "run",
      "The pipeline on a scan nobody labelled: fit the body, segment the garments, make the "
      "pattern (seams, panels, flattening, placement, stitches); writes OUT/fit/, OUT/segment/, "
      "OUT/pattern/ (pattern.json for GarmentCode, pattern.pdf/.svg at 1:1, pattern.dxf, "
      "panels.obj + stitches.json + body_rest.obj for cloth simulators), OUT/drape/ (the pattern "
      "sewn and draped, compared with the scan) and OUT/report.json");
  addFitOptions(run, r->fit);
  addPatternOptions(run, r->pattern);
  addPrintOptions(run, r->print);
  run->add_flag("--faithful", r->faithful,
                "Algorithm 1 as written, slower (see segment --faithful)");
  run->add_flag("--drape,!--no-drape", r->drape,
                "Sew the pattern, drape it on the rest body and measure it against the scanned "
                "garments (OUT/drape/): on by default; --no-drape skips it (about 10–30 s for a "
                "t-shirt and trousers)");
  run->add_option("--drape-steps", r->drapeSteps,
                  fmt::format("Step budget (1/60 s each) of each drape phase, sewing and draping "
                              "(default {} and {}); a drape that has not settled by then is "
                              "reported, not written",
                              DrapeOptions{}.sewMaxSteps, DrapeOptions{}.drapeMaxSteps))
      ->check(CLI::NonNegativeNumber);
  run->add_option("--drape-coarse-edge", r->drapeCoarseEdgeMm,
                  "Edge (mm) of the coarse mesh the pattern is first sewn and draped on, before "
                  "the drape is carried onto the pattern's own mesh and settled there; 0 sews "
                  "and drapes at the pattern's resolution only (slower: minutes)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  run->add_option("--remesh-edge", r->remeshEdgeMm,
                  "Target edge length (mm) of the panels' triangulation (panels.obj, the drape)")
      ->capture_default_str()
      ->check(CLI::Range(2.0, 100.0));
  out.push_back({run, [r](Progress& progress) { return runRun(*r, progress); }});

  auto s = std::make_shared<FitSuiteCommand>();
  auto* suite = app.add_subcommand(
      "fit-suite",
      "Fit every scan of a bench-suite folder (optionally turned about the vertical, optionally "
      "segmented with the fitted body) and score it against its truth.json (fit_suite.md, "
      "fit_suite.json)");
  suite->add_option("DIR", s->suiteDir, "Folder written by scan2pattern bench-suite")->required();
  suite->add_option("-o,--output", s->out, "Output folder")->capture_default_str();
  suite->add_option("--model", s->model, "Body model (see fit --model)")->capture_default_str();
  suite->add_option("--only", s->only, "Run only the entry of this name");
  suite
      ->add_option("--rotations", s->rotations,
                   "Degrees about the vertical to turn each scan by before fitting, e.g. "
                   "0,90,180,270,37")
      ->delimiter(',')
      ->capture_default_str();
  suite->add_flag("--segment", s->segment,
                  "Also segment with the fitted body and score the garments (the end-to-end run)");
  suite->add_flag("--faithful", s->faithful, "Algorithm 1 as written when segmenting");
  suite->add_flag("--no-nonrigid", s->noNonrigid,
                  "Skip the non-rigid full fit (joint figures do not depend on it)");
  suite->add_flag("--single-start", s->singleStart,
                  "Fit from the geometric pose initialisation alone (see fit --single-start)");
  suite->add_flag("--drape", s->drape,
                  "With --segment: also sew and drape each pattern and compare it with the "
                  "scanned garments (PRESET/drape/, the drape columns; issue 19's suite check)");
  out.push_back({suite, [s](Progress& progress) { return runFitSuite(*s, progress); }});
}

}  // namespace s2p::app
