// body: a body model, shaped, posed, measured, with its feature points.
#include <fmt/format.h>

#include <fstream>
#include <memory>

#include "app/commands.h"
#include "body/body_json.h"
#include "body/body_source.h"
#include "body/measurements.h"
#include "body/posing.h"
#include "core/error.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

struct BodyCommand {
  std::string model = "mannequin";
  std::string shape;
  std::string measurements;
  std::string pose = "apose";
  std::string out = "body_out";
};

BodyPose resolvePose(const BodyModel& model, const Eigen::VectorXd& shape,
                     const std::string& pose) {
  if (pose == "rest") return standardPose(model, shape, StandardPose::Rest);
  if (pose == "apose") return standardPose(model, shape, StandardPose::APose);
  if (pose == "tpose") return standardPose(model, shape, StandardPose::TPose);
  if (pose == "drape") return standardPose(model, shape, StandardPose::DrapePose);
  return readPoseJson(pose, model);
}

int runBody(const BodyCommand& cmd, Progress& progress) {
  progress.begin("load body model " + cmd.model);
  const BodyModel model = loadBodyModel(cmd.model);
  progress.end();
  Eigen::VectorXd shape = parseShapeAssignments(model, cmd.shape);
  if (!cmd.measurements.empty()) {
    progress.begin("fit shape to " + cmd.measurements);
    std::ifstream in(cmd.measurements);
    if (!in) throw IoError("cannot read measurements file " + cmd.measurements);
    json j;
    try {
      j = json::parse(in);
    } catch (const json::exception& e) {
      throw FormatError(fmt::format("{} is not JSON: {}", cmd.measurements, e.what()));
    }
    MeasurementFitOptions fitOpt;
    fitOpt.initial = shape;
    shape = fitShapeToMeasurements(model, toTargets(measurementsFromJson(j)), fitOpt);
    progress.end();
  }
  progress.begin("pose, measure, features");
  BodyParams params{shape, resolvePose(model, shape, cmd.pose)};
  const PosedBody posed = poseBody(model, params);
  const BodyMeasurements measured = measureRestBody(model, shape);
  const FeatureSet features = computeFeatures(model, shape);
  progress.end();

  const fs::path out = cmd.out;
  fs::create_directories(out);
  progress.begin("write outputs");
  writeObj(out / "body.obj", posed.mesh);
  json bj = bodyToJson(model, params, posed);
  bj["measurements"] = toJson(measured);
  writeJson(out / "body.json", bj);
  writeJson(out / "features.json", featuresToJson(features, posed.mesh));
  const Scene scene = featureScene(posed.mesh, features);
  RenderOptions ro;
  ro.views = {View::Front, View::Left, View::Back};
  ro.captions = {"front", "left", "back"};
  writePng(out / "body_features.png", renderScene(scene, ro));
  progress.end();
  fmt::print(
      "{}: {} vertices, {} joints, {} shape parameters; height {:.3f} m, chest {:.1f} cm, "
      "waist {:.1f} cm, hip {:.1f} cm\n",
      model.source, model.numVertices(), model.numJoints(), model.numShapes(), measured.height,
      100 * measured.chestGirth, 100 * measured.waistGirth, 100 * measured.hipGirth);
  fmt::print("wrote {}/: body.obj, body.json, features.json, body_features.png\n", out.string());
  return 0;
}

}  // namespace

void addBodyCommand(CLI::App& app, Commands& out) {
  auto o = std::make_shared<BodyCommand>();
  auto* cmd = app.add_subcommand(
      "body", "Make a body: load a model, shape and pose it, measure it, find its feature points");
  cmd->add_option("--model", o->model, "mannequin | mpfb2:DIR | smpl:FILE.npz")
      ->capture_default_str();
  cmd->add_option("--shape", o->shape,
                  "Shape parameters as name=value,... (mannequin: height, chest, waist, hip, "
                  "shoulder, arm, inseam, neck, thigh, upper_arm; +1 = +1 cm)");
  cmd->add_option("--measurements", o->measurements,
                  "JSON of target measurements in metres (e.g. {\"chest_girth\": 1.0}); the "
                  "shape is fitted to them");
  cmd->add_option("--pose", o->pose, "rest | apose | tpose | drape (A-pose, legs apart: where patterns are placed) | FILE.json (joint: axis-angle)")
      ->capture_default_str();
  cmd->add_option("-o,--output", o->out, "Output folder")->capture_default_str();
  out.push_back({cmd, [o](Progress& progress) { return runBody(*o, progress); }});
}

}  // namespace s2p::app
