#include "app/fit_output.h"

#include <fmt/format.h>

#include "app/commands.h"
#include "body/body_json.h"
#include "body/measurements.h"
#include "core/error.h"
#include "export/preview.h"
#include "io/write_mesh.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

Eigen::Vector3d applied(const Eigen::Affine3d& T, const json& xyz) {
  return T * Eigen::Vector3d(xyz[0].get<double>(), xyz[1].get<double>(), xyz[2].get<double>());
}

TriMesh inFileFrame(const TriMesh& normalised, const Scan& scan) {
  TriMesh m = normalised;
  m.V = (normalised.V * scan.toInputFrame.linear().transpose()).rowwise() +
        scan.toInputFrame.translation().transpose();
  return m;
}

}  // namespace

json fitBodyJson(const BodyModel& model, const ScanFit& fit, const Scan& scan) {
  json j = bodyToJson(model, fit.fit.params, fit.fit.body);
  const Eigen::Affine3d toFile = scan.toInputFrame * fit.toScan;
  for (const char* key : {"joints", "canonical"})
    for (auto& [name, xyz] : j[key].items()) {
      const Eigen::Vector3d p = applied(toFile, xyz);
      xyz = {p.x(), p.y(), p.z()};
    }
  json m = json::array();
  for (int r = 0; r < 4; ++r)
    m.push_back({toFile.matrix()(r, 0), toFile.matrix()(r, 1), toFile.matrix()(r, 2),
                 toFile.matrix()(r, 3)});
  j["to_scan_file"] = m;
  j["full_mesh"] = "body_full.obj";
  std::vector<std::string> warnings = fit.warnings;
  try {
    j["measurements"] = toJson(measureRestBody(model, fit.fit.params.shape));
  } catch (const InputError& e) {
    // A tape measure failing on an unusual shape does not make the fit wrong.
    j["measurements"] = nullptr;
    warnings.push_back(std::string("no measurements: ") + e.what());
  }
  json stages = json::array();
  for (const FitStageReport& s : fit.fit.stages)
    stages.push_back({{"name", s.name},
                      {"cycle", s.cycle},
                      {"seconds", s.seconds},
                      {"iterations", s.iterations},
                      {"cost_before", s.costBefore},
                      {"cost_after", s.costAfter}});
  json timings = json::object();
  for (const auto& [name, s] : fit.timings) timings[name] = s;
  json cues = json::object();
  for (const OrientationCue& c : fit.orientation.cues) cues[c.name] = c.vote;
  j["fit"] = {{"initialisation", fit.initialisation},
              {"start", fitStartJson(fit)},
              {"yaw_degrees", fit.orientation.yaw * 180 / M_PI},
              {"orientation_confidence", fit.orientation.confidence},
              {"orientation_cues", cues},
              {"inside_or_within_5mm", fit.fit.insideOrNear},
              {"full_fit_mean_distance_m", fit.fullMeanDistance},
              {"seconds", fit.seconds},
              {"timings", timings},
              {"stages", stages},
              {"warnings", warnings},
              {"frame",
               "joints, canonical and to_scan_file: the scan file's frame and units; "
               "shape, pose and translation: the body model's frame"}};
  return j;
}

void writeFit(const fs::path& dir, const Scan& scan, const BodyModel& model, const ScanFit& fit) {
  fs::create_directories(dir);
  const TriMesh fitted = fit.fittedInScanFrame(), full = fit.fullInScanFrame();
  writeObj(dir / "body_fit.obj", inFileFrame(fitted, scan));
  writeObj(dir / "body_full.obj", inFileFrame(full, scan));
  writeJson(dir / "body.json", fitBodyJson(model, fit, scan));

  // The scan, semi-transparent, over the fitted body (normalised frame).
  Scene scene;
  scene.meshes.push_back({&fitted, nullptr, Rgb{225, 160, 120}});
  SceneMesh sm{&scan.mesh, nullptr, Rgb{150, 170, 200}, 0.45f};
  if (scan.colourSource != ColourSource::None) sm.colour = &scan.colour;
  scene.meshes.push_back(sm);
  RenderOptions ro;
  ro.heightPx = 900;
  ro.views = {View::Front, View::Back};
  ro.captions = {"front", "back"};
  writePng(dir / "fit_front.png", renderScene(scene, ro));
  ro.views = {View::Left, View::Right};
  ro.captions = {"left", "right"};
  writePng(dir / "fit_side.png", renderScene(scene, ro));
}

nlohmann::json fitStartJson(const ScanFit& fit) {
  nlohmann::json scores = nlohmann::json::object();
  for (const StartScore& s : fit.startScores) scores[s.name] = 1000 * s.score;
  return {{"name", fit.start}, {"score_mm", 1000 * fit.startScore}, {"scores_mm", scores}};
}

void printFit(const ScanFit& fit) {
  fmt::print("facing {:.0f}° (confidence {:.2f}), pose from {} (start: {}); {:.1f} s (",
             fit.orientation.yaw * 180 / M_PI, fit.orientation.confidence, fit.initialisation,
             fit.start, fit.seconds);
  for (size_t i = 0; i < fit.timings.size(); ++i)
    fmt::print("{}{} {:.1f} s", i ? ", " : "", fit.timings[i].first, fit.timings[i].second);
  fmt::print(
      ")\n  {:.1f} % of the body inside the scan or within 5 mm; full fit {:.1f} mm from "
      "the scan on average\n",
      100 * fit.fit.insideOrNear, 1000 * fit.fullMeanDistance);
  for (const std::string& w : fit.warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace s2p::app
