// Shared pieces of the command line: scan loading, the info summary, previews, JSON output.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>

#include "app/commands.h"
#include "core/error.h"
#include "core/mesh_topology.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {

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
    throw CLI::ValidationError("--units",
                               "unknown units '" + opt.units + "': use auto, mm, cm, dm or m");
  const auto up = parseUpAxis(opt.up);
  if (!up)
    throw CLI::ValidationError("--up", "unknown axis '" + opt.up + "': use auto, +y, -y, +z or -z");
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
  out.pieces = normalizePerson(out.scan, normOpt, out.normalize);
  for (const auto& w : out.pieces.warnings) {
    progress.message("clean-up: " + w);
    out.normalize.warnings.push_back("clean-up: " + w);
  }
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
  json pieces = json::array();
  for (const PieceInfo& p : s.pieces.pieces)
    pieces.push_back({{"role", toString(p.role)},
                      {"vertices", p.vertices},
                      {"faces", p.faces},
                      {"area_m2", p.area},
                      {"distance_m", p.distance}});
  j["pieces"] = {{"kept", s.pieces.keptPieces},
                 {"floor", s.pieces.floorPieces},
                 {"floaters", s.pieces.floaterPieces},
                 {"dropped_vertices", s.pieces.droppedVertices},
                 {"dropped_area_m2", s.pieces.droppedArea},
                 {"pieces", pieces}};
  j["seconds"] = {
      {"read", s.read.seconds}, {"cleanup", s.cleanup.seconds}, {"normalize", s.normalizeSeconds}};
  json warnings = json::array();
  for (const auto& w : s.read.warnings) warnings.push_back(w);
  for (const auto& w : s.cleanup.warnings) warnings.push_back(w);
  for (const auto& w : s.normalize.warnings) warnings.push_back(w);
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

std::vector<View> parseViews(const std::string& list, const std::string& option) {
  std::vector<View> views;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const auto v = parseView(name);
    if (!v)
      throw CLI::ValidationError(option,
                                 fmt::format("unknown view '{}': use front, back, left, right, "
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

// Feature splines as closed/open polylines through their anchors, sign points (+ blue, − magenta)
// and region points coloured by label, drawn over the body (paper Fig. 4 and Fig. 11).
Scene featureScene(const TriMesh& mesh, const FeatureSet& fs) {
  Scene scene;
  scene.meshes.push_back({&mesh, nullptr, Rgb{215, 205, 195}});
  auto addCurves = [&](const CurveFeatures& c, Rgb colour) {
    for (const auto& s : c.splines) {
      Polyline line;
      line.points.resize(static_cast<int>(s.anchors.size()), 3);
      for (size_t i = 0; i < s.anchors.size(); ++i)
        line.points.row(i) = s.anchors[i].position(mesh);
      line.colour = colour;
      line.closed = s.closed;
      line.widthPx = 3;
      scene.points.push_back({line.points, Rgb{20, 140, 20}, 4});
      scene.lines.push_back(std::move(line));
    }
    PointSet pos{Eigen::MatrixX3d(0, 3), Rgb{30, 60, 230}, 6},
        neg{Eigen::MatrixX3d(0, 3), Rgb{220, 30, 200}, 6};
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

json readJsonFile(const fs::path& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw IoError(fmt::format("cannot read {} {}", what, path.string()));
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw FormatError(fmt::format("{} {} is not JSON: {}", what, path.string(), e.what()));
  }
}

void writeJson(const fs::path& path, const json& j) {
  writeFileAtomically(path, j.dump(2) + "\n");
}

std::vector<fs::path> suiteTruths(const fs::path& suiteDir, const std::string& only) {
  if (!fs::is_directory(suiteDir))
    throw IoError(fmt::format("{} is not a folder (make one with scan2pattern bench-suite -o DIR)",
                              suiteDir.string()));
  std::vector<fs::path> truths;
  for (const auto& e : fs::directory_iterator(suiteDir))
    if (e.is_directory() && fs::exists(e.path() / "truth.json") &&
        (only.empty() || e.path().filename() == only))
      truths.push_back(e.path() / "truth.json");
  std::sort(truths.begin(), truths.end());
  if (truths.empty())
    throw IoError(fmt::format("no <name>/truth.json under {}{}", suiteDir.string(),
                              only.empty() ? "" : " for the entry " + only));
  return truths;
}

void requireWritableFolder(const fs::path& dir) {
  // Nothing is created: the folder itself, or the nearest folder above it that exists, must
  // take a file (a probe written and removed), so that bad input later leaves no folder behind.
  std::error_code ec;
  fs::path existing = fs::absolute(dir, ec);
  while (!existing.empty() && !fs::exists(existing, ec) && existing != existing.parent_path())
    existing = existing.parent_path();
  const fs::path probe = existing / ".scan2pattern_write_test";
  bool ok = fs::is_directory(existing, ec);
  if (ok) {
    std::ofstream f(probe);
    ok = f && (f << "x") && f.flush();
  }
  fs::remove(probe, ec);
  if (!ok)
    throw IoError(
        fmt::format("cannot write into the output folder {}: choose another with -o "
                    "or make it writable",
                    dir.string()));
}

void addPatternOptions(CLI::App* cmd, PatternOptions& pattern) {
  cmd->add_option_function<double>(
      "--noise-filter",
      [&pattern](double mm) {
        if (!(mm >= 0 && mm <= 20))
          throw CLI::ValidationError("--noise-filter", "must be between 0 and 20 mm");
        pattern.flat.denoise.scale = mm / 1000;
      },
      "Length of the filter that takes the scanner's noise out of each garment panel before "
      "it is flattened, mm (default 5; 0: flatten the scan as it is). Noise makes every scanned "
      "edge longer than the cloth, and so the pattern too big");
  cmd->add_flag_callback(
      "--keep-fused-contacts", [&pattern] { pattern.panels.openFusedContacts = false; },
      "Leave a sleeve the scan fused to the trunk below the armpit (an arm hanging against the "
      "side) as the scan shows it: the armhole then runs down the crease. By default the contact "
      "is opened and the cloth it hid (the sleeve's underside, the side under the arm) is "
      "supplied, and panels.json says so");
}

void addPrintOptions(CLI::App* cmd, PrintOptions& print) {
  cmd->add_option_function<double>(
      "--seam-allowance",
      [&print](double mm) {
        if (!(mm >= 0 && mm <= 100))
          throw CLI::ValidationError("--seam-allowance", "must be between 0 and 100 mm");
        print.seamAllowance = mm / 1000;
      },
      "Seam allowance of the cut line in pattern.svg/.pdf/.dxf, mm (default 10; 0: cut on "
      "the sew line)");
  cmd->add_option_function<std::string>(
      "--paper",
      [&print](const std::string& p) {
        if (p == "a4")
          print.paper = Paper::A4;
        else if (p == "letter")
          print.paper = Paper::Letter;
        else
          throw CLI::ValidationError("--paper", "must be a4 or letter");
      },
      "Paper the PDF is tiled on for home printing: a4 (default) or letter");
}

}  // namespace s2p::app
