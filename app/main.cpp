// The `scan2pattern` command: parses options, calls the library, maps errors to exit codes.
// Everything it does is a library call first; this file only wires options to calls.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <fmt/format.h>
#include <iostream>
#include <new>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "body/body_json.h"
#include "body/body_source.h"
#include "body/features.h"
#include "body/measurements.h"
#include "body/posing.h"
#include "core/error.h"
#include "core/mesh_topology.h"
#include "core/progress.h"
#include "export/preview.h"
#include "io/cleanup.h"
#include "io/demo_scan.h"
#include "io/normalize.h"
#include "io/read_scan.h"
#include "io/write_mesh.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p {
namespace {

// === Shared: read + clean + normalise, as every command that takes a SCAN does.

struct LoadedScan {
  Scan scan;
  ReadReport read;
  CleanupReport cleanup;
  NormalizeReport normalize;
  double normalizeSeconds = 0;
};

struct LoadOptions {
  std::string units = "auto";
  std::string up = "auto";
};

void addLoadOptions(CLI::App* cmd, LoadOptions& opt) {
  cmd->add_option("--units", opt.units, "Units of the file: auto, mm, cm, dm, m")
      ->capture_default_str();
  cmd->add_option("--up", opt.up, "Up axis of the file: auto, +y, -y, +z, -z")
      ->capture_default_str();
}

LoadedScan loadScan(const fs::path& path, const LoadOptions& opt, Progress& progress) {
  NormalizeOptions normOpt;
  const auto units = parseUnits(opt.units);
  if (!units)
    throw CLI::ValidationError("--units", "unknown units '" + opt.units + "': use auto, mm, cm, dm or m");
  const auto up = parseUpAxis(opt.up);
  if (!up) throw CLI::ValidationError("--up", "unknown axis '" + opt.up + "': use auto, +y, -y, +z or -z");
  normOpt.units = *units;
  normOpt.up = *up;
  LoadedScan out;
  progress.begin(fmt::format("read {}", path.filename().string()));
  out.scan = readScan(path, {}, &out.read);
  progress.end();
  for (const auto& w : out.read.warnings) progress.message("warning: " + w);
  progress.begin("clean up");
  out.cleanup = cleanScan(out.scan);
  progress.end();
  for (const auto& w : out.cleanup.warnings) progress.message("warning: " + w);
  const auto t0 = std::chrono::steady_clock::now();
  out.normalize = normalizeScan(out.scan, normOpt);
  out.normalizeSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

// === info

json infoJson(const LoadedScan& s) {
  const TriMesh& m = s.scan.mesh;
  const MeshTopology topo(m.F, m.numVertices());
  const BoundingBox box = boundingBox(m.V);
  const ManifoldReport& mr = topo.manifoldness();
  json j;
  j["file"] = s.scan.sourcePath;
  j["format"] = s.read.format;
  j["vertices"] = m.numVertices();
  j["faces"] = m.numFaces();
  j["components"] = topo.numComponents();
  j["boundary_loops"] = topo.boundaryLoops().size();
  j["euler_characteristic"] = topo.eulerCharacteristic();
  j["manifold"] = mr.isManifold();
  j["non_manifold_edges"] = mr.nonManifoldEdges.size();
  j["non_manifold_vertices"] = mr.nonManifoldVertices.size();
  j["bbox_min_m"] = {box.min.x(), box.min.y(), box.min.z()};
  j["bbox_max_m"] = {box.max.x(), box.max.y(), box.max.z()};
  j["height_m"] = s.normalize.heightMetres;
  j["units"] = toString(s.normalize.units);
  j["units_detected"] = s.normalize.unitsDetected;
  j["up_axis"] = toString(s.normalize.up);
  j["up_detected"] = s.normalize.upDetected;
  j["colour_source"] = toString(s.scan.colourSource);
  j["texture"] = s.scan.texture ? s.scan.texture->path : "";
  j["cleanup"] = {{"welded_vertices", s.cleanup.weldedVertices},
                  {"degenerate_faces", s.cleanup.degenerateFaces},
                  {"duplicate_faces", s.cleanup.duplicateFaces},
                  {"unreferenced_vertices", s.cleanup.unreferencedVertices},
                  {"split_non_manifold_vertices", s.cleanup.splitNonManifoldVertices},
                  {"largest_hole_perimeter_m", s.cleanup.largestHolePerimeter}};
  j["seconds"] = {{"read", s.read.seconds},
                  {"cleanup", s.cleanup.seconds},
                  {"normalize", s.normalizeSeconds}};
  json warnings = json::array();
  for (const auto& w : s.read.warnings) warnings.push_back(w);
  for (const auto& w : s.cleanup.warnings) warnings.push_back(w);
  j["warnings"] = warnings;
  return j;
}

void printInfo(const json& j) {
  fmt::print("file            {} ({})\n", j["file"].get<std::string>(),
             j["format"].get<std::string>());
  fmt::print("vertices        {}\n", j["vertices"].get<int>());
  fmt::print("faces           {}\n", j["faces"].get<int>());
  fmt::print("components      {}\n", j["components"].get<int>());
  fmt::print("boundary loops  {} (holes)\n", j["boundary_loops"].get<size_t>());
  fmt::print("euler char.     {}\n", j["euler_characteristic"].get<int>());
  fmt::print("manifold        {} ({} non-manifold edges, {} non-manifold vertices)\n",
             j["manifold"].get<bool>() ? "yes" : "no", j["non_manifold_edges"].get<size_t>(),
             j["non_manifold_vertices"].get<size_t>());
  const auto& mn = j["bbox_min_m"];
  const auto& mx = j["bbox_max_m"];
  fmt::print("bounding box    [{:.3f}, {:.3f}, {:.3f}] .. [{:.3f}, {:.3f}, {:.3f}] m\n",
             mn[0].get<double>(), mn[1].get<double>(), mn[2].get<double>(), mx[0].get<double>(),
             mx[1].get<double>(), mx[2].get<double>());
  fmt::print("height          {:.3f} m\n", j["height_m"].get<double>());
  fmt::print("units           {}{}\n", j["units"].get<std::string>(),
             j["units_detected"].get<bool>() ? " (detected)" : " (given)");
  fmt::print("up axis         {}{}\n", j["up_axis"].get<std::string>(),
             j["up_detected"].get<bool>() ? " (detected)" : " (given)");
  fmt::print("colour          {}\n", j["colour_source"].get<std::string>());
  const auto& c = j["cleanup"];
  fmt::print(
      "clean-up        {} welded, {} degenerate and {} duplicate faces dropped, {} unreferenced "
      "vertices, {} non-manifold vertices split\n",
      c["welded_vertices"].get<int>(), c["degenerate_faces"].get<int>(),
      c["duplicate_faces"].get<int>(), c["unreferenced_vertices"].get<int>(),
      c["split_non_manifold_vertices"].get<int>());
  const auto& t = j["seconds"];
  fmt::print("time            read {:.3f} s, clean-up {:.3f} s, normalise {:.3f} s\n",
             t["read"].get<double>(), t["cleanup"].get<double>(), t["normalize"].get<double>());
  for (const auto& w : j["warnings"]) fmt::print("warning         {}\n", w.get<std::string>());
}

// === preview

std::vector<View> parseViews(const std::string& list) {
  std::vector<View> views;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const auto v = parseView(name);
    if (!v)
      throw CLI::ValidationError(
          "--views", fmt::format("unknown view '{}': use front, back, left, right, "
                                 "three-quarter",
                                 name));
    views.push_back(*v);
  }
  return views;
}

Image renderScan(const Scan& scan, const std::vector<View>& views, int heightPx) {
  Scene scene;
  SceneMesh sm;
  sm.mesh = &scan.mesh;
  if (scan.colourSource != ColourSource::None) sm.colour = &scan.colour;
  scene.meshes.push_back(sm);
  RenderOptions ro;
  ro.views = views;
  ro.heightPx = heightPx;
  return renderScene(scene, ro);
}

MeshAttributes colourAttributes(const Scan& scan) {
  MeshAttributes attrs;
  if (scan.colourSource != ColourSource::None) attrs.colour = &scan.colour;
  return attrs;
}

// === body: a body model, shaped, posed, measured, with its feature points

struct BodyCommand {
  std::string model = "mannequin";
  std::string shape;
  std::string measurements;
  std::string pose = "apose";
  std::string out = "body_out";
};

BodyPose resolvePose(const BodyModel& model, const Eigen::VectorXd& shape, const std::string& pose) {
  if (pose == "rest") return standardPose(model, shape, StandardPose::Rest);
  if (pose == "apose") return standardPose(model, shape, StandardPose::APose);
  if (pose == "tpose") return standardPose(model, shape, StandardPose::TPose);
  return readPoseJson(pose, model);
}

// Feature splines as closed/open polylines through their anchors, sign points (+ blue, − magenta)
// and region points coloured by label, drawn over the body (paper Fig. 4 and Fig. 11).
Scene featureScene(const TriMesh& mesh, const FeatureSet& fs) {
  Scene scene;
  scene.meshes.push_back({&mesh, nullptr, Rgb{215, 205, 195}});
  auto addCurves = [&](const CurveFeatures& c, Rgb colour) {
    for (const auto& s : c.splines) {
      Polyline line;
      line.points.resize(static_cast<int>(s.anchors.size()), 3);
      for (size_t i = 0; i < s.anchors.size(); ++i) line.points.row(i) = s.anchors[i].position(mesh);
      line.colour = colour;
      line.closed = s.closed;
      line.widthPx = 3;
      scene.points.push_back({line.points, Rgb{20, 140, 20}, 4});
      scene.lines.push_back(std::move(line));
    }
    PointSet pos{Eigen::MatrixX3d(0, 3), Rgb{30, 60, 230}, 6}, neg{Eigen::MatrixX3d(0, 3), Rgb{220, 30, 200}, 6};
    for (const auto& sp : c.signs) {
      PointSet& set = sp.value > 0 ? pos : neg;
      set.points.conservativeResize(set.points.rows() + 1, 3);
      set.points.row(set.points.rows() - 1) = sp.point.position(mesh);
    }
    scene.points.push_back(pos);
    scene.points.push_back(neg);
  };
  addCurves(fs.upperSkin, Rgb{230, 40, 40});
  addCurves(fs.lowerSkin, Rgb{230, 140, 20});
  addCurves(fs.upperLower, Rgb{150, 40, 200});
  for (const auto& seam : fs.seams) addCurves(seam, Rgb{40, 120, 220});
  const Rgb regionColour[] = {{250, 200, 150}, {230, 60, 60}, {60, 90, 220}, {40, 40, 40}};
  for (int l = 0; l < 4; ++l) {
    PointSet set{Eigen::MatrixX3d(0, 3), regionColour[l], 2.5f};
    for (const auto& r : fs.regions)
      if (static_cast<int>(r.label) == l) {
        set.points.conservativeResize(set.points.rows() + 1, 3);
        set.points.row(set.points.rows() - 1) = r.point.position(mesh);
      }
    scene.points.push_back(set);
  }
  return scene;
}

void writeJson(const fs::path& path, const json& j) {
  writeFileAtomically(path, j.dump(2) + "\n");
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
  fmt::print("{}: {} vertices, {} joints, {} shape parameters; height {:.3f} m, chest {:.1f} cm, "
             "waist {:.1f} cm, hip {:.1f} cm\n",
             model.source, model.numVertices(), model.numJoints(), model.numShapes(),
             measured.height, 100 * measured.chestGirth, 100 * measured.waistGirth,
             100 * measured.hipGirth);
  fmt::print("wrote {}/: body.obj, body.json, features.json, body_features.png\n", out.string());
  return 0;
}

// === demo: the main job on the built-in demo scan (until the pipeline exists: a mannequin
// "scan" in garment colours, read back, cleaned, normalised, summarised and pictured).

int runDemo(const fs::path& outDir, Progress& progress) {
  fs::create_directories(outDir);
  progress.begin("generate demo scan (mannequin in A-pose)");
  const BodyModel model = loadBodyModel("mannequin");
  const Eigen::VectorXd shape = Eigen::VectorXd::Zero(model.numShapes());
  const PosedBody posed =
      poseBody(model, {shape, standardPose(model, shape, StandardPose::APose)});
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
  fmt::print("\nwrote {}/: demo_scan.ply (input: mm, +Z up), demo_normalized.glb (metres, +Y up), "
             "info.json, demo_preview.png, body_features.png\n",
             outDir.string());
  return 0;
}

}  // namespace
}  // namespace s2p

int main(int argc, char** argv) {
  using namespace s2p;
  CLI::App app{
      "scan2pattern: sewing patterns from a 3D scan of a clothed person\n"
      "(Bang, Korosteleva and Lee, \"Estimating Garment Patterns from Static Scan Data\", "
      "CGF 2021)"};
  app.set_version_flag("--version", std::string("scan2pattern ") + S2P_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 file not found or not writable,\n"
      "4 file format (garbage, truncated, unsupported), 5 unusable input (no faces,\n"
      "non-finite coordinates, not a person), 6 topology, 7 solver failure.");
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "No progress output on stderr");

  // info
  auto* info = app.add_subcommand("info", "Read a scan, clean and normalise it, print a summary");
  std::string infoPath;
  bool infoJsonOut = false;
  LoadOptions infoLoad;
  info->add_option("SCAN", infoPath, "Scan file: .obj (+.mtl, texture), .ply, .gltf, .glb")
      ->required();
  info->add_flag("--json", infoJsonOut, "Print the summary as JSON");
  addLoadOptions(info, infoLoad);

  // convert
  auto* convert =
      app.add_subcommand("convert", "Read, clean and normalise a scan, then write it out");
  std::string convIn, convOut;
  bool convKeepFrame = false;
  LoadOptions convLoad;
  convert->add_option("SCAN", convIn, "Input scan file")->required();
  convert->add_option("OUT", convOut, "Output mesh: .ply, .obj or .glb")->required();
  convert->add_flag("--input-frame", convKeepFrame,
                    "Write in the input's units and axes instead of metres, +Y up");
  addLoadOptions(convert, convLoad);

  // preview
  auto* preview = app.add_subcommand("preview", "Render a mesh to a PNG picture");
  std::string prevIn, prevOut, prevViews = "front";
  int prevHeight = 1024;
  LoadOptions prevLoad;
  preview->add_option("MESH", prevIn, "Mesh or scan file")->required();
  preview->add_option("-o,--output", prevOut, "Output PNG")->required();
  preview->add_option("--views", prevViews, "Comma-separated: front, back, left, right, "
                                            "three-quarter")
      ->capture_default_str();
  preview->add_option("--height", prevHeight, "Image height in pixels")
      ->capture_default_str()
      ->check(CLI::Range(64, 8192));
  addLoadOptions(preview, prevLoad);

  // body
  auto* body = app.add_subcommand(
      "body", "Make a body: load a model, shape and pose it, measure it, find its feature points");
  BodyCommand bodyCmd;
  body->add_option("--model", bodyCmd.model, "mannequin | mpfb2:DIR | smpl:FILE.npz")
      ->capture_default_str();
  body->add_option("--shape", bodyCmd.shape,
                   "Shape parameters as name=value,... (mannequin: height, chest, waist, hip, "
                   "shoulder, arm, inseam, neck, thigh, upper_arm; +1 = +1 cm)");
  body->add_option("--measurements", bodyCmd.measurements,
                   "JSON of target measurements in metres (e.g. {\"chest_girth\": 1.0}); the "
                   "shape is fitted to them");
  body->add_option("--pose", bodyCmd.pose, "rest | apose | tpose | FILE.json (joint: axis-angle)")
      ->capture_default_str();
  body->add_option("-o,--output", bodyCmd.out, "Output folder")->capture_default_str();

  // demo
  auto* demo = app.add_subcommand("demo", "Run the main job on the built-in demo scan");
  std::string demoOut = "demo_out";
  demo->add_option("-o,--output", demoOut, "Output folder")->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(ExitCode::Usage);
  }

  Progress progress(quiet ? Progress::Mode::Silent : Progress::Mode::Auto);
  try {
    if (*info) {
      Progress& p = infoJsonOut ? Progress::silent() : progress;
      const LoadedScan s = loadScan(infoPath, infoLoad, p);
      const json j = infoJson(s);
      if (infoJsonOut)
        std::cout << j.dump(2) << "\n";
      else
        printInfo(j);
    } else if (*convert) {
      LoadedScan s = loadScan(convIn, convLoad, progress);
      TriMesh out = s.scan.mesh;
      if (convKeepFrame) out.V = (s.scan.toInputFrame * out.V.transpose()).transpose();
      writeMesh(convOut, out, colourAttributes(s.scan));
      progress.message(fmt::format("wrote {} ({} vertices, {} faces)", convOut,
                                   out.numVertices(), out.numFaces()));
    } else if (*preview) {
      const std::vector<View> views = parseViews(prevViews);
      const LoadedScan s = loadScan(prevIn, prevLoad, progress);
      progress.begin("render");
      writePng(prevOut, renderScan(s.scan, views, prevHeight));
      progress.end();
      progress.message("wrote " + prevOut);
    } else if (*body) {
      return runBody(bodyCmd, progress);
    } else if (*demo) {
      return runDemo(demoOut, progress);
    }
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : static_cast<int>(ExitCode::Usage);
  } catch (const s2p::Error& e) {
    std::fflush(stdout);
    fmt::print(stderr, "\nscan2pattern: error: {}\n", e.what());
    return static_cast<int>(e.exitCode());
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "\nscan2pattern: error: out of memory; try a smaller or decimated scan\n");
    return static_cast<int>(ExitCode::Internal);
  } catch (const std::exception& e) {
    fmt::print(stderr, "\nscan2pattern: internal error (please report): {}\n", e.what());
    return static_cast<int>(ExitCode::Internal);
  }
  return 0;
}
