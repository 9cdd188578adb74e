// demo: the main job on the built-in demo scan.
#include <fmt/format.h>

#include <memory>

#include "app/commands.h"
#include "body/body_source.h"
#include "body/posing.h"
#include "io/demo_scan.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

// === demo: the main job on the built-in demo scan (until the pipeline exists: a mannequin
// "scan" in garment colours, read back, cleaned, normalised, summarised and pictured).

int runDemo(const fs::path& outDir, Progress& progress) {
  fs::create_directories(outDir);
  progress.begin("generate demo scan (mannequin in A-pose)");
  const BodyModel model = loadBodyModel("mannequin");
  const Eigen::VectorXd shape = Eigen::VectorXd::Zero(model.numShapes());
  const PosedBody posed = poseBody(model, {shape, standardPose(model, shape, StandardPose::APose)});
  const Scan demo = makeDemoScan(posed.mesh);
  const fs::path scanPath = outDir / "demo_scan.ply";
  writePly(scanPath, demo.mesh, colourAttributes(demo));
  progress.end();
  LoadedScan loaded = loadScan(scanPath, {}, progress);
  const json info = infoJson(loaded);
  printInfo(info);
  progress.begin("write outputs");
  writeMesh(outDir / "demo_normalized.glb", loaded.scan.mesh, colourAttributes(loaded.scan));
  writePng(outDir / "demo_preview.png",
           renderScan(loaded.scan, {View::Front, View::Left, View::Back}, 1024));
  writeJson(outDir / "info.json", info);
  const FeatureSet features = computeFeatures(model, shape);
  writePng(outDir / "body_features.png", [&] {
    RenderOptions ro;
    ro.views = {View::Front, View::Back};
    return renderScene(featureScene(posed.mesh, features), ro);
  }());
  progress.end();
  fmt::print(
      "\nwrote {}/: demo_scan.ply (input: mm, +Z up), demo_normalized.glb (metres, +Y up), "
      "info.json, demo_preview.png, body_features.png\n",
      outDir.string());
  return 0;
}

}  // namespace

void addDemoCommand(CLI::App& app, Commands& out) {
  auto outDir = std::make_shared<std::string>("demo_out");
  auto* cmd = app.add_subcommand("demo", "Run the main job on the built-in demo scan");
  cmd->add_option("-o,--output", *outDir, "Output folder")->capture_default_str();
  out.push_back({cmd, [outDir](Progress& progress) { return runDemo(*outDir, progress); }});
}

}  // namespace s2p::app
