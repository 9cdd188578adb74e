// panels: the pattern stages (paper §6.1–6.3) alone, on a fit + segment output: seam lines,
// panels, flattening, placement, stitches and the pattern files.
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <memory>

#include "app/commands.h"
#include "app/drape_output.h"
#include "app/pattern_files.h"
#include "app/pattern_output.h"
#include "app/segment_output.h"
#include "core/error.h"
#include "eval/pattern_metrics.h"
#include "io/read_obj.h"
#include "synth/truth.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

struct PanelsCommand {
  std::string scan;
  std::string body;
  std::string truth;
  std::string segmentation;
  std::string score;  // a synthetic scan's truth.json to score the panels against
  bool armholeBodyParts = false;
  bool drape = false;   // also sew and drape the pattern (OUT/drape/, drape.json)
  int drapeSteps = -1;  // step budget of each drape phase; −1: DrapeOptions' defaults
  double drapeCoarseEdgeMm = 1000 * DrapeStageOptions{}.coarseEdge;  // 0: one level only
  std::string out = "panels_out";
  LoadOptions load;
  PrintOptions print;
  PatternOptions pattern;
};

// A garment OBJ written by `segment`, back in the normalised frame, its vertices as the file
// indexes them (read_obj.h: a weld by position would join distinct vertices of the exact cut).
TriMesh readGarment(const fs::path& path, const Scan& scan) {
  TriMesh m = readObjGeometry(path);
  const Eigen::Affine3d toNormal = scan.toInputFrame.inverse();
  for (int v = 0; v < m.numVertices(); ++v)
    m.V.row(v) = (toNormal * Eigen::Vector3d(m.V.row(v).transpose())).transpose();
  return m;
}

int runPanelsCommand(const PanelsCommand& cmd, Progress& progress) {
  if (cmd.truth.empty() == cmd.body.empty())
    throw CLI::ValidationError("--truth/--body", "give exactly one of --truth and --body");
  requireWritableFolder(cmd.out);
  json bodyJson;
  fs::path bodyDir;
  if (!cmd.body.empty()) {
    bodyJson = readJsonFile(cmd.body, "body file");
    bodyDir = fs::path(cmd.body).parent_path();
  } else {
    const json t = readJsonFile(cmd.truth, "truth file");
    if (!t.contains("body") || !t["body"].is_object())
      throw FormatError(fmt::format("truth file {} has no \"body\" object", cmd.truth));
    bodyJson = t["body"];
  }
  const LoadedScan loaded = loadScan(cmd.scan, cmd.load, progress);
  const PosedFeatures body = poseBodyForScan(bodyJson, loaded.scan, progress, bodyDir);
  const fs::path segDir = cmd.segmentation;
  const json garments = readJsonFile(segDir / "garments.json", "garment list");
  PanelsInput in;
  in.body = body.body;
  in.features = body.features;
  in.canonical = body.canonical;
  if (cmd.armholeBodyParts && body.model && body.model->numVertices() == body.body.numVertices())
    in.bodyLimbWeight = limbWeights(*body.model);
  try {
    for (const json& g : garments.at("garments")) {
      PanelsInput::Garment pg;
      pg.name = g.at("name").get<std::string>();
      pg.kind = pg.name == "onepiece" ? GarmentKind::OnePiece
                : pg.name == "lower"  ? GarmentKind::Lower
                                      : GarmentKind::Upper;
      pg.mesh = readGarment(segDir / g.at("file").get<std::string>(), loaded.scan);
      const std::vector<int> origin = g.at("face_origin").get<std::vector<int>>();
      if (static_cast<int>(origin.size()) != pg.mesh.numFaces())
        throw FormatError(fmt::format("{}: garment '{}' has {} faces but {} face_origin entries",
                                      (segDir / "garments.json").string(), pg.name,
                                      pg.mesh.numFaces(), origin.size()));
      pg.faceOrigin =
          Eigen::Map<const Eigen::VectorXi>(origin.data(), static_cast<int>(origin.size()));
      in.garments.push_back(std::move(pg));
    }
  } catch (const json::exception& e) {
    throw FormatError(fmt::format("{} is not a garment list written by `segment`: {}",
                                  (segDir / "garments.json").string(), e.what()));
  }
  PipelineResult run;  // the pattern, and its drape when asked
  run.pattern = runPattern(in, body, loaded.scan.mesh, cmd.pattern, progress);
  const PatternResult& r = run.pattern;
  progress.begin("write the pattern files");
  writePanels(cmd.out, loaded.scan, r.panels);
  writeFlatPattern(cmd.out, loaded.scan, r.panels, r.flat);
  writePatternFiles(cmd.out, loaded.scan, r, cmd.print);
  writeJson(fs::path(cmd.out) / "placement.json", placementToJson(r));
  if (!cmd.score.empty()) {
    const PatternScore ps = scorePattern(r.panels, readTruth(cmd.score), in.body, in.canonical);
    // Each cuff's lowest point against the armpit: where a sleeve meets the trunk from its cuff
    // up (arms pressed to the sides), the armhole seam can come no higher than this.
    const BodyFrame frame(in.canonical);
    json cuffs = json::object();
    for (const GarmentPanels& g : r.panels.garments)
      for (int pi : g.panels)
        for (const PanelEdge& e : r.panels.panels[pi].edges) {
          if (!e.opening || e.name.find("_cuff") == std::string::npos) continue;
          const double armpit = armpitHeight(in.body, frame, e.name.rfind("left", 0) == 0);
          double low = std::numeric_limits<double>::infinity();
          for (int v : e.vertices)
            low = std::min(low, frame.height(r.panels.panels[pi].mesh.V.row(v).transpose()));
          const std::string key = g.name + ":" + e.name;
          if (std::isfinite(armpit) && std::isfinite(low))
            cuffs[key] = std::min(cuffs.value(key, 1e9), 1000 * (low - armpit));
        }
    json garments = json::array();
    for (const GarmentPatternScore& g : ps.garments)
      garments.push_back({{"truth", g.truthGarment},
                          {"expected_type", g.expectedType},
                          {"found_type", g.foundType},
                          {"found_panels", g.foundPanels},
                          {"type_ok", g.typeOk},
                          {"panels_ok", g.panelsOk}});
    json score = {{"garments", garments},
                  {"panels", ps.panels},
                  {"disks", ps.disks},
                  {"unpartnered", ps.unpartnered},
                  {"max_partner_mismatch", ps.maxPartnerMismatch},
                  {"cuff_minus_armpit_mm", cuffs}};
    score.update(patternScoreFigures(ps));
    writeJson(fs::path(cmd.out) / "pattern_score.json", score);
  }
  progress.end();
  if (cmd.drape) {
    // The drape compares with the garments as `segment` cut them (read above).
    // Which garment was completed under the other (the drape's layers): garments.json, or for
    // a folder written before it said so, boundaries.json's "occlusion".
    std::string occlusion;
    if (fs::exists(segDir / "boundaries.json"))
      occlusion = readJsonFile(segDir / "boundaries.json", "boundaries").value("occlusion", "");
    for (const PanelsInput::Garment& g : in.garments) {
      GarmentPiece piece;
      piece.name = g.name;
      piece.mesh = g.mesh;
      piece.occluded = occlusion == g.name + "_occluded";
      for (const json& j : garments.at("garments"))
        if (j.value("name", "") == g.name && j.contains("occluded"))
          piece.occluded = j.at("occluded").get<bool>();
      run.segmentation.garments.push_back(std::move(piece));
    }
    DrapeStageOptions options;
    options.enabled = true;
    if (cmd.drapeSteps >= 0)
      options.drape.sewMaxSteps = options.drape.drapeMaxSteps = cmd.drapeSteps;
    options.coarseEdge = cmd.drapeCoarseEdgeMm / 1000;
    run.drape = runDrapeStage(run.pattern, run.segmentation, body, options, &progress);
    progress.end();
    writeDrape(fs::path(cmd.out) / "drape", run);
    fs::create_directories(fs::path(cmd.out) / "drape");
    writeJson(fs::path(cmd.out) / "drape" / "drape.json", drapeToJson(run));
  }
  printPanels(r.panels);
  printFlatPattern(r.panels, r.flat);
  printPatternFiles(r);
  if (cmd.drape) printDrape(run);
  fmt::print(
      "wrote {}/: pattern.json, pattern.svg, pattern.pdf, pattern.dxf, pattern.png, "
      "panels.obj, stitches.json, body_rest.obj, placement.json, panels.json, "
      "panels_3d.obj, panels.png, flat.json, panels_flat.obj, pattern_strain.png\n",
      cmd.out);
  return 0;
}

}  // namespace

void addPatternCommands(CLI::App& app, Commands& out) {
  auto c = std::make_shared<PanelsCommand>();
  auto* cmd = app.add_subcommand(
      "panels",
      "The pattern (paper §6) on a fit + segment output: seam lines, disk-shaped panels with "
      "tagged edges, garment types, flattening, Bézier outlines, remeshing, placement around the "
      "rest body and stitches; writes pattern.json (GarmentCode), pattern.svg/.pdf (1:1), "
      "pattern.dxf (DXF-AAMA), panels.obj + stitches.json + body_rest.obj and the figures");
  cmd->add_option("scan", c->scan, "The scan the segmentation was made on")->required();
  cmd->add_option("--body", c->body, "body.json from `fit` (its body_full.obj beside it)");
  cmd->add_option("--truth", c->truth, "A synthetic scan's truth.json: use its true body");
  cmd->add_option("--segmentation", c->segmentation,
                  "The folder `segment` wrote (garments.json and the garment OBJs)")
      ->required();
  cmd->add_option("--score", c->score,
                  "A synthetic scan's truth.json: write pattern_score.json (garment types, panel "
                  "sets, armhole − armpit, mirror areas, side seams against it)");
  cmd->add_flag("--armhole-body-parts", c->armholeBodyParts,
                "Also hold the armhole seam's function at +1 where the fitted body calls the "
                "garment trunk (closest body vertex with an agreeing normal, by its skinning "
                "weights): keeps a sleeve joined to the torso's side from turning the side into "
                "sleeve. Experimental: not yet on in `run`");
  cmd->add_flag("--drape", c->drape,
                "Also sew the pattern, drape it on the rest body and measure it against the "
                "segmented garments: OUT/drape/ (draped.obj, drape_compare.png, drape.json)");
  cmd->add_option("--drape-steps", c->drapeSteps,
                  "Step budget (1/60 s each) of each drape phase (see run --drape-steps)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--drape-coarse-edge", c->drapeCoarseEdgeMm,
                  "Edge (mm) of the coarse mesh sewn first (see run --drape-coarse-edge)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("-o,--out", c->out, "Output folder (default panels_out)");
  addLoadOptions(cmd, c->load);
  addPatternOptions(cmd, c->pattern);
  addPrintOptions(cmd, c->print);
  out.push_back({cmd, [c](Progress& progress) { return runPanelsCommand(*c, progress); }});
}

}  // namespace s2p::app
