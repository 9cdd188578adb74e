#include "app/segment_output.h"

#include <fmt/format.h>

#include <cmath>
#include <map>

#include "app/commands.h"
#include "body/body_json.h"
#include "core/error.h"
#include "eval/evaluation_files.h"
#include "export/png.h"
#include "export/preview.h"
#include "io/read_obj.h"
#include "io/read_scan.h"
#include "io/write_mesh.h"
#include "synth/synthesize.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

Eigen::MatrixX3d toFrame(const Eigen::Affine3d& t, const Eigen::MatrixX3d& P) {
  return ((t.linear() * P.transpose()).colwise() + t.translation()).transpose();
}

// §5.2's wide sets of gap candidates: each one's ΔE00 from the garment beside it and whether it
// was taken as a gap.
json gapSets(const BoundaryReport& b) {
  json out = json::array();
  for (const auto& [deltaE, gap] : b.gapSetDeltaE)
    out.push_back({{"delta_e_from_garment", deltaE}, {"gap", gap}});
  return out;
}

json curvesJson(const std::vector<Eigen::MatrixX3d>& curves, const std::vector<bool>& closed,
                const Eigen::Affine3d& toInput) {
  json out = json::array();
  for (size_t c = 0; c < curves.size(); ++c) {
    const Eigen::MatrixX3d P = toFrame(toInput, curves[c]);
    json pts = json::array();
    for (int i = 0; i < P.rows(); ++i) pts.push_back({P(i, 0), P(i, 1), P(i, 2)});
    out.push_back({{"closed", static_cast<bool>(closed[c])}, {"points", pts}});
  }
  return out;
}

double polylineLength(const Eigen::MatrixX3d& P, bool closed) {
  double len = 0;
  for (int i = 0; i + 1 < P.rows(); ++i) len += (P.row(i + 1) - P.row(i)).norm();
  if (closed && P.rows() > 1) len += (P.row(0) - P.row(P.rows() - 1)).norm();
  return len;
}

}  // namespace

namespace {

// "to_scan_file": a 4×4 row-major matrix; absent: identity (the body is in the file's frame).
Eigen::Affine3d toScanFile(const json& bodyJson) {
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  if (!bodyJson.contains("to_scan_file")) return T;
  const json& m = bodyJson["to_scan_file"];
  try {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) T.matrix()(r, c) = m.at(r).at(c).get<double>();
  } catch (const json::exception&) {
    throw FormatError("the body JSON's \"to_scan_file\" is not a 4×4 matrix of numbers");
  }
  if (!T.matrix().allFinite() || std::abs(T.linear().determinant()) < 1e-12)
    throw InputError("the body JSON's \"to_scan_file\" is not an invertible transform");
  return T;
}

// The non-rigid fit written next to body.json (same faces as the model, in the scan file's
// frame); an OBJ reader may split vertices per corner, so positions are gathered by face.
Eigen::MatrixX3d readFullMesh(const fs::path& path, const BodyModel& model) {
  ReadOptions ro;
  ro.loadTexture = false;
  const Scan s = readScan(path, ro);
  if (s.mesh.numFaces() != model.rest.numFaces())
    throw FormatError(fmt::format("{} has {} faces, but the body model {} has {}: not its full "
                                  "fit (rerun scan2pattern fit)",
                                  path.string(), s.mesh.numFaces(), model.source,
                                  model.rest.numFaces()));
  Eigen::MatrixX3d V(model.numVertices(), 3);
  for (int f = 0; f < s.mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) V.row(model.rest.F(f, k)) = s.mesh.V.row(s.mesh.F(f, k));
  return V;
}

}  // namespace

PosedFeatures poseBodyForScan(const json& bodyJson, const Scan& scan, Progress& progress,
                              const fs::path& jsonDir) {
  progress.begin("pose body");
  BodyFromJson b = bodyFromJson(bodyJson);
  PosedFeatures out;
  out.body = std::move(b.posed.mesh);
  out.features = std::move(b.features);
  out.canonical = toFrame(toScanFile(bodyJson), b.posed.canonical);
  out.params = b.params;
  out.toGarments = scan.toInputFrame.inverse() * toScanFile(bodyJson);
  out.model = std::make_shared<const BodyModel>(std::move(b.model));
  const bool full = bodyJson.contains("full_mesh") && bodyJson["full_mesh"].is_string() &&
                    !jsonDir.empty();
  const fs::path fullPath = full ? jsonDir / bodyJson["full_mesh"].get<std::string>() : fs::path();
  if (full && fs::exists(fullPath)) {
    out.body.V = readFullMesh(fullPath, *out.model);
  } else {
    if (full)
      progress.message(fmt::format("{} is missing: the features are carried by the posed body",
                                   fullPath.string()));
    out.body.V = toFrame(toScanFile(bodyJson), out.body.V);
  }
  out.body.V = toFrame(scan.toInputFrame.inverse(), out.body.V);
  out.canonical = toFrame(scan.toInputFrame.inverse(), out.canonical);
  progress.end();
  return out;
}

TriMesh underBodyForScan(const json& bodyJson, const PosedFeatures& body, const Scan& scan,
                         const fs::path& jsonDir) {
  const fs::path fitted = jsonDir / "body_fit.obj";
  if (jsonDir.empty() || !bodyJson.contains("full_mesh") || !fs::exists(fitted)) return body.body;
  TriMesh m = readObjGeometry(fitted);
  m.V = toFrame(scan.toInputFrame.inverse(), m.V);
  return m;
}

// NaN (no body under the clothes) as null: JSON has no NaN.
static json nullIfNan(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

json segmentationToJson(const SegmentOutput& out, const Eigen::Affine3d& toInput) {
  const Segmentation& s = out.segmentation;
  // One entry per label pair (eval's format), holding the curves of every run with that pair.
  std::map<std::pair<int, int>, json> pairs;
  json runs = json::array();
  for (const BoundaryReport& b : s.boundaries) {
    for (size_t c = 0; c < b.finalCurves.size(); ++c) {
      int a = static_cast<int>(b.garment), o = static_cast<int>(b.otherLabels[c]);
      if (a > o) std::swap(a, o);
      json& e = pairs[{a, o}];
      if (e.is_null())
        e = {{"labels", {toString(static_cast<Label>(a)), toString(static_cast<Label>(o))}},
             {"curves", json::array()},
             {"length_m", 0.0},
             {"from", b.name}};
      e["curves"].push_back(curvesJson({b.finalCurves[c]}, {b.finalClosed[c]}, toInput)[0]);
      e["length_m"] = e["length_m"].get<double>() + polylineLength(b.finalCurves[c], b.finalClosed[c]);
    }
    runs.push_back({{"name", b.name},
                    {"garment", toString(b.garment)},
                    {"iterations", b.iterations},
                    {"converged", b.converged},
                    {"vanished", b.vanished},
                    {"seconds", b.seconds},
                    {"optimised_vertices", b.optimisedVertices},
                    {"coarse_seconds", b.coarseSeconds},
                    {"anchors", b.anchors},
                    {"dropped_anchors", b.droppedAnchors},
                    {"sign_points", b.signs},
                    {"dropped_sign_points", b.droppedSigns},
                    {"gap_pass", b.gapPass},
                    {"gap_applied", b.gapApplied},
                    {"gap_shift_m", b.gapShift},
                    {"plane_pass", b.planePass},
                    {"gap_sets", gapSets(b)},
                    {"islands_removed", b.islandsRemoved},
                    {"geometry_weight", b.geometryWeight},
                    {"high_side", b.highSide},
                    {"hem_contrast_m", b.hemContrast},
                    {"timings", {{"setup", b.timings.setup},
                                 {"regularisation", b.timings.regularisation},
                                 {"isoline", b.timings.isoline},
                                 {"biharmonic", b.timings.biharmonic},
                                 {"geodesic", b.timings.geodesic}}},
                    {"initial_curves", curvesJson(b.initialCurves, b.initialClosed, toInput)},
                    {"final_curves", curvesJson(b.finalCurves, b.finalClosed, toInput)}});
  }
  json boundaries = json::array();
  for (auto& [k, e] : pairs) boundaries.push_back(e);
  json garments = json::array();
  for (const GarmentPiece& g : s.garments)
    garments.push_back({{"name", g.name},
                        {"label", toString(g.label)},
                        {"file", g.name + ".obj"},
                        {"vertices", g.mesh.numVertices()},
                        {"faces", g.mesh.numFaces()},
                        {"area_m2", surfaceArea(g.mesh)},
                        {"occluded", g.occluded},
                        {"completed_area_m2", g.completedArea}});
  json notes = json::array();
  for (const auto& n : s.notes) notes.push_back(n);
  json held = json::array();
  for (const HeldObject& o : s.heldObjects) {
    const Eigen::Vector3d c = toInput * o.centroid;
    held.push_back({{"area_m2", o.area},
                    {"max_offset_m", o.maxOffset},
                    {"centroid", {c.x(), c.y(), c.z()}},
                    {"span_degrees", o.span},
                    {"beside_level_m", o.besideLevel},
                    {"edge_lowered_m", o.lowered},
                    {"beside_delta_e", std::isfinite(o.besideDeltaE) ? json(o.besideDeltaE)
                                                                     : json(nullptr)}});
  }
  return {{"segmenter", out.segmenter},
          {"held_objects", held},
          {"hair_area_m2", s.hairArea},
          {"hair_seed_area_m2", s.hairSeedArea},
          {"layout", toString(s.layout)},
          {"occlusion", toString(s.occlusion)},
          {"shoes", s.shoes},
          {"delta_e", {{"upper_lower", s.upperLowerDeltaE},
                       {"upper_skin", s.upperSkinDeltaE},
                       {"lower_skin", s.lowerSkinDeltaE},
                       {"foot_skin", s.footSkinDeltaE}}},
          {"skin_like_fraction", {{"upper", s.upperSkinLike}, {"lower", s.lowerSkinLike}}},
          {"skin_delta_e", s.skinDeltaE},
          {"geometric_cues", s.geometricCues},
          {"region_offset_m", {{"skin", nullIfNan(s.skinOffset)},
                               {"upper", nullIfNan(s.upperOffset)},
                               {"lower", nullIfNan(s.lowerOffset)}}},
          {"region_points", s.regionPoints},
          {"dropped_region_points", s.droppedRegionPoints},
          {"seconds", s.seconds},
          {"boundaries", boundaries},
          {"runs", runs},
          {"garments", garments},
          {"notes", notes},
          {"frame", "the scan file's frame and units"}};
}

void writeSegmentation(const fs::path& dir, const Scan& scan,
                       const SegmentOutput& out) {
  const Segmentation& s = out.segmentation;
  fs::create_directories(dir);
  TriMesh scanOut = scan.mesh;
  scanOut.V = toFrame(scan.toInputFrame, scan.mesh.V);
  MeshAttributes attrs = colourAttributes(scan);
  attrs.vertexLabels = &s.vertexLabel;
  attrs.faceLabels = &s.faceLabel;
  writePly(dir / "segmentation.ply", scanOut, attrs);

  json garmentMaps = json::array();
  for (const GarmentPiece& g : s.garments) {
    TriMesh m = g.mesh;
    m.V = toFrame(scan.toInputFrame, g.mesh.V);
    MeshAttributes ga;
    if (g.colour.rows() == m.numVertices()) ga.colour = &g.colour;
    writeObj(dir / (g.name + ".obj"), m, ga);
    garmentMaps.push_back({{"name", g.name},
                           {"file", g.name + ".obj"},
                           {"occluded", g.occluded},
                           {"face_origin", std::vector<int>(g.faceOrigin.data(),
                                                            g.faceOrigin.data() + g.faceOrigin.size())}});
  }
  writeJson(dir / "garments.json",
            {{"scan", scan.sourcePath},
             {"note", "face_origin[i]: the scan face (segmentation.ply) face i lies in"},
             {"garments", garmentMaps}});
  // An MRF labelling has no curves: eval then scores its label edges, so no boundaries.json.
  const bool curves = out.segmenter != "mrf";
  fs::remove(dir / (curves ? "segment_report.json" : "boundaries.json"));
  writeJson(dir / (curves ? "boundaries.json" : "segment_report.json"),
            segmentationToJson(out, scan.toInputFrame));

  // Previews (normalised frame): the scan with initial (blue) and final (red) boundaries, and
  // the labels.
  RenderOptions ro;
  ro.views = {View::Front, View::Back};
  ro.captions = {"front", "back"};
  ro.heightPx = 900;
  Scene scene;
  SceneMesh sm;
  sm.mesh = &scan.mesh;
  if (scan.colourSource != ColourSource::None) sm.colour = &scan.colour;
  scene.meshes.push_back(sm);
  for (const BoundaryReport& b : s.boundaries) {
    for (size_t c = 0; c < b.initialCurves.size(); ++c)
      scene.lines.push_back({b.initialCurves[c], Rgb{40, 90, 230}, 2, b.initialClosed[c], false});
    for (size_t c = 0; c < b.finalCurves.size(); ++c)
      scene.lines.push_back({b.finalCurves[c], Rgb{230, 30, 30}, 3, b.finalClosed[c], false});
  }
  writePng(dir / "segment_boundaries.png", renderScene(scene, ro));
  const Eigen::MatrixX3d byLabel = labelColours(s.vertexLabel);
  Scene labels;
  labels.meshes.push_back({&scan.mesh, &byLabel});
  for (const GarmentPiece& g : s.garments)
    if (g.occluded) labels.meshes.push_back({&g.mesh, nullptr, Rgb{120, 120, 120}, 0.35f});
  writePng(dir / "segment_labels.png", renderScene(labels, ro));
}

SegmentScore scoreSegmentation(const fs::path& truthPath, const fs::path& outDir) {
  const LoadedEvaluation ev = loadEvaluation(resolveEvaluationFiles(truthPath, outDir));
  SegmentScore out;
  out.evaluation = evaluate(ev.input());
  writeJson(outDir / "evaluation.json", evaluationToJson(out.evaluation));
  double meanSum = 0;
  int scored = 0;
  for (const BoundaryScore& b : out.evaluation.boundaries) {
    if (b.missing) {
      out.missing += fmt::format("{}{}|{}", out.missing.empty() ? "" : " ", toString(b.a),
                                 toString(b.b));
      continue;
    }
    meanSum += b.pooled.mean;
    out.worstP95 = std::max(out.worstP95, b.pooled.p95);
    out.worstRoughness = std::max(out.worstRoughness, b.roughness);
    ++scored;
  }
  out.boundaryMean = scored ? meanSum / scored : 0.0;
  return out;
}

void printSegmentation(const Segmentation& s) {
  if (s.decided)
    fmt::print("layout {}, occlusion {}, shoes {}; {:.1f} s\n", toString(s.layout),
               toString(s.occlusion), s.shoes ? "yes" : "no", s.seconds);
  else
    fmt::print("labels per vertex (no layout, occlusion or shoe decision); {:.1f} s\n", s.seconds);
  for (const BoundaryReport& b : s.boundaries)
    fmt::print("  {:4} {:3} iterations{}, {} curve(s), {:.2f} s{}, optimised on {} vertices\n",
               b.name, b.iterations, b.converged ? "" : " (not converged)", b.finalCurves.size(),
               b.seconds,
               b.gapApplied ? fmt::format(", gap pass moved it {:.0f} mm", 1000 * b.gapShift) : "",
               b.optimisedVertices);
  for (const GarmentPiece& g : s.garments)
    fmt::print("  {:8} {} faces, {:.3f} m²{}\n", g.name, g.mesh.numFaces(), surfaceArea(g.mesh),
               g.occluded ? fmt::format(" ({:.3f} m² completed under the other garment)",
                                        g.completedArea)
                          : "");
  for (const auto& n : s.notes) fmt::print("  note: {}\n", n);
}

std::string garmentFileList(const Segmentation& s) {
  std::string out;
  for (const GarmentPiece& g : s.garments) out += g.name + ".obj, ";
  return out;
}

SegmentOutput segmentWithMrf(const Scan& scan, const TriMesh& body, const TriMesh& underBody,
                             const FeatureSet& features, const SegmentationOptions& options,
                             Progress& progress) {
  return {segmentScanMrf(scan.mesh, scan.colour, body, underBody, features, options, {},
                         &progress),
          "mrf"};
}

}  // namespace s2p::app
