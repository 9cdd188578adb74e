// segment: garment segmentation of a scan with a known posed body (paper §5).
#include <fmt/format.h>

#include <fstream>
#include <memory>

#include "app/commands.h"
#include "app/segment_output.h"
#include "body/body_json.h"
#include "body/body_source.h"
#include "core/error.h"

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
  bool fast = false;
  bool noGapFilling = false;
  LoadOptions load;
};

json readJsonFile(const fs::path& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw IoError(fmt::format("cannot read {} {}", what, path.string()));
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw FormatError(fmt::format("{} {} is not JSON: {}", what, path.string(), e.what()));
  }
}

int runSegment(const SegmentCommand& cmd, Progress& progress) {
  if (cmd.truth.empty() == cmd.body.empty())
    throw CLI::ValidationError("--truth/--body", "give exactly one of --truth and --body");
  if (cmd.segmenter != "curve" && cmd.segmenter != "mrf")
    throw CLI::ValidationError("--segmenter", "use curve (the paper's method) or mrf");
  json bodyJson;
  if (!cmd.truth.empty()) {
    const json t = readJsonFile(cmd.truth, "truth file");
    if (!t.contains("body") || !t["body"].is_object())
      throw FormatError(fmt::format("truth file {} has no \"body\" object", cmd.truth));
    bodyJson = t["body"];
  } else {
    bodyJson = readJsonFile(cmd.body, "body file");
  }
  if (!bodyJson.contains("source") || !bodyJson["source"].is_string())
    throw FormatError("the body JSON has no \"source\" (mannequin, mpfb2:DIR or smpl:FILE)");

  const LoadedScan loaded = loadScan(cmd.scan, cmd.load, progress);
  const Scan& scan = loaded.scan;
  progress.begin("pose body " + bodyJson["source"].get<std::string>());
  const BodyModel model = loadBodyModel(bodyJson["source"].get<std::string>());
  const BodyParams params = bodyParamsFromJson(bodyJson, model);
  PosedBody posed = poseBody(model, params);
  // The body JSON is in the scan file's frame; the scan was normalised.
  const Eigen::Affine3d toScan = scan.toInputFrame.inverse();
  posed.mesh.V = ((toScan.linear() * posed.mesh.V.transpose()).colwise() + toScan.translation())
                     .transpose();
  const FeatureSet features = computeFeatures(model, params.shape);
  progress.end();

  SegmentationOptions options;
  options.boundary.faithful = !cmd.fast;
  options.gapFilling = !cmd.noGapFilling;
  const SegmentOutput result =
      cmd.segmenter == "mrf"
          ? segmentWithMrf(scan, posed.mesh, features, options, progress)
          : SegmentOutput{segmentScan(scan.mesh, scan.colour, posed.mesh, features, options,
                                      &progress),
                          "curve"};
  progress.begin("write outputs");
  writeSegmentation(cmd.out, scan, posed.mesh, result);
  progress.end();
  printSegmentation(result.segmentation);
  fmt::print("wrote {}/: segmentation.ply, {}boundaries.json, garments.json, "
             "segment_boundaries.png, segment_labels.png\n",
             cmd.out, garmentFileList(result.segmentation));
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
  cmd->add_flag("--fast", o->fast,
                "Fast boundary optimisation: signed distance from the regularised isoline, no "
                "biharmonic in the loop");
  cmd->add_flag("--no-gap-filling", o->noGapFilling,
                "Skip the second pass for gap-filling triangles (§5.2)");
  addLoadOptions(cmd, o->load);
  out.push_back({cmd, [o](Progress& progress) { return runSegment(*o, progress); }});
}

}  // namespace s2p::app
