#include "app/pattern_output.h"

#include <fmt/format.h>

#include "app/commands.h"
#include "export/pattern_sheet.h"
#include "export/png.h"
#include "export/preview.h"
#include "io/write_mesh.h"
#include "pattern/grain_frame.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

Eigen::Vector3d toFrame(const Eigen::Affine3d& t, const Eigen::Vector3d& p) {
  return t * p;
}

json point(const Eigen::Affine3d& t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = toFrame(t, p);
  return {q.x(), q.y(), q.z()};
}

// A distinct colour per panel (golden-ratio hues).
Rgb panelColour(int i) {
  const double h = std::fmod(0.13 + 0.618034 * i, 1.0) * 6;
  const double x = 1 - std::abs(std::fmod(h, 2) - 1);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h)) {
    case 0:
      r = 1, g = x;
      break;
    case 1:
      r = x, g = 1;
      break;
    case 2:
      g = 1, b = x;
      break;
    case 3:
      g = x, b = 1;
      break;
    case 4:
      r = x, b = 1;
      break;
    default:
      r = 1, b = x;
      break;
  }
  const auto c = [](double v) { return static_cast<std::uint8_t>(60 + 170 * v); };
  return {c(r), c(g), c(b)};
}

}  // namespace

json patternScoreFigures(const PatternScore& ps) {
  const auto byName = [](const std::vector<std::pair<std::string, double>>& v, double scale) {
    json o = json::object();
    for (const auto& [n, x] : v) o[n] = scale * x;
    return o;
  };
  return {{"armhole_minus_armpit_mm", byName(ps.armholeToArmpit, 1000)},
          {"mirror_area_diff", byName(ps.mirrorAreaDiff, 1)},
          {"mirror_cloth_area_diff", byName(ps.mirrorClothAreaDiff, 1)},
          {"side_seam_degrees", byName(ps.sideSeamAngle, 1)},
          {"side_seam_limb_degrees", byName(ps.sideSeamLimbAngle, 1)}};
}

json panelsToJson(const PanelsResult& r, const Eigen::Affine3d& toInput) {
  json garments = json::array();
  for (const GarmentPanels& g : r.garments) {
    json panels = json::array(), openings = json::array(), seams = json::array();
    for (int p : g.panels) panels.push_back(r.panels[p].name);
    for (const Opening& o : g.openings)
      openings.push_back({{"name", o.name},
                          {"limb", toString(o.limb)},
                          {"place_on_limb", o.t},
                          {"length_m", o.length},
                          {"centroid", point(toInput, o.centroid)}});
    for (const SeamLine& s : g.seams) {
      json curves = json::array();
      for (const IsolineCurve& c : s.line.curves) {
        json pts = json::array();
        for (const IsolinePoint& q : c.points) pts.push_back(point(toInput, q.position));
        curves.push_back({{"closed", c.closed}, {"points", pts}});
      }
      seams.push_back({{"name", s.name},
                       {"kind", toString(s.kind)},
                       {"features", s.features},
                       {"kept", s.kept},
                       {"removed_why", s.removedWhy},
                       {"anchors", s.anchors},
                       {"dropped_anchors", s.droppedAnchors},
                       {"contact_anchors", s.contactAnchors},  // kept: not in dropped_anchors
                       {"sign_points", s.signs},
                       {"dropped_sign_points", s.droppedSigns},
                       {"dropped_with_their_pair", s.pairedDrops},
                       {"trunk_points", s.trunkPoints},
                       {"sleeve_points", s.sleevePoints},
                       {"splines_kept", s.splinesKept},
                       {"splines_removed", s.splinesRemoved},
                       {"islands_removed", s.islandsRemoved},
                       {"length_m", s.line.length()},
                       {"seconds", s.seconds},
                       {"curves", curves}});
    }
    garments.push_back({{"name", g.name},
                        {"kind", toString(g.kind)},
                        {"type", g.type},
                        {"panels", panels},
                        {"openings", openings},
                        {"seams", seams},
                        {"notes", g.notes}});
  }
  json panels = json::array();
  for (const Panel& p : r.panels) {
    json edges = json::array(), corners = json::array();
    for (size_t e = 0; e < p.edges.size(); ++e) {
      const PanelEdge& edge = p.edges[e];
      corners.push_back(point(toInput, p.mesh.V.row(edge.vertices.front()).transpose()));
      json j = {{"name", edge.name},       {"kind", edge.opening ? "opening" : "seam"},
                {"from_corner", e},        {"to_corner", (e + 1) % p.edges.size()},
                {"length_m", edge.length}, {"vertices", edge.vertices.size()}};
      if (!edge.opening && edge.partnerPanel >= 0)
        j["partner"] = {{"panel", r.panels[edge.partnerPanel].name},
                        {"panel_index", edge.partnerPanel},
                        {"edge", edge.partnerEdge}};
      edges.push_back(j);
    }
    panels.push_back({{"name", p.name},
                      {"garment", p.garment},
                      {"vertices", p.mesh.numVertices()},
                      {"faces", p.mesh.numFaces()},
                      {"area_m2", p.area},
                      {"cut_open", p.cutOpen},
                      {"corners", corners},
                      {"edges", edges}});
  }
  return {{"frame", "the scan file's frame and units"},
          {"garments", garments},
          {"panels", panels},
          {"warnings", r.warnings},
          {"seconds", r.seconds}};
}

void writePanels(const fs::path& dir, const Scan& scan, const PanelsResult& r) {
  fs::create_directories(dir);
  writeJson(dir / "panels.json", panelsToJson(r, scan.toInputFrame));
  // panels_3d.obj: every panel, one group each, in the scan file's frame.
  int nV = 0, nF = 0;
  for (const Panel& p : r.panels) {
    nV += p.mesh.numVertices();
    nF += p.mesh.numFaces();
  }
  TriMesh all;
  all.V.resize(nV, 3);
  all.F.resize(nF, 3);
  Eigen::VectorXi group(nF);
  std::vector<std::string> names;
  Eigen::MatrixX3d colour(nV, 3);
  int v0 = 0, f0 = 0;
  for (size_t i = 0; i < r.panels.size(); ++i) {
    const Panel& p = r.panels[i];
    const Rgb c = panelColour(static_cast<int>(i));
    for (int v = 0; v < p.mesh.numVertices(); ++v) {
      all.V.row(v0 + v) = toFrame(scan.toInputFrame, p.mesh.V.row(v).transpose()).transpose();
      colour.row(v0 + v) << c.r / 255.0, c.g / 255.0, c.b / 255.0;
    }
    for (int f = 0; f < p.mesh.numFaces(); ++f) {
      all.F.row(f0 + f) = p.mesh.F.row(f).array() + v0;
      group[f0 + f] = static_cast<int>(i);
    }
    names.push_back(p.garment + "_" + p.name);
    v0 += p.mesh.numVertices();
    f0 += p.mesh.numFaces();
  }
  MeshAttributes attrs;
  attrs.faceGroups = &group;
  attrs.groupNames = &names;
  if (nF > 0) writeObj(dir / "panels_3d.obj", all, attrs);

  // panels.png: the scan in grey, the panels coloured, the seam lines (panel edges that are
  // seams) in black, from front, back and both sides.
  Scene scene;
  scene.meshes.push_back({&scan.mesh, nullptr, Rgb{215, 215, 215}});
  std::vector<TriMesh> meshes(r.panels.size());
  for (size_t i = 0; i < r.panels.size(); ++i) {
    // Lifted 2 mm off the scan along the normals so that the panels win the depth test.
    meshes[i] = r.panels[i].mesh;
    meshes[i].V += 0.002 * vertexNormals(meshes[i]);
    scene.meshes.push_back({&meshes[i], nullptr, panelColour(static_cast<int>(i))});
    for (const PanelEdge& e : r.panels[i].edges) {
      if (e.opening) continue;
      Eigen::MatrixX3d P(static_cast<int>(e.vertices.size()), 3);
      for (size_t k = 0; k < e.vertices.size(); ++k)
        P.row(static_cast<int>(k)) = meshes[i].V.row(e.vertices[k]);
      scene.lines.push_back(
          {P, e.name == "cut" ? Rgb{200, 0, 200} : Rgb{20, 20, 20}, 2.5f, false, false});
    }
  }
  RenderOptions ro;
  ro.views = {View::Front, View::Back, View::Left, View::Right};
  ro.captions = {"front", "back", "left", "right"};
  ro.heightPx = 800;
  writePng(dir / "panels.png", renderScene(scene, ro));
}

void printPanels(const PanelsResult& r) {
  for (const GarmentPanels& g : r.garments) {
    std::string names;
    for (int p : g.panels) names += (names.empty() ? "" : ", ") + r.panels[p].name;
    fmt::print("{}: {} ({} panels: {})\n", g.name, g.type, g.panels.size(), names);
    for (const std::string& n : g.notes) fmt::print("  {}\n", n);
  }
  for (const std::string& w : r.warnings) fmt::print("  warning: {}\n", w);
  fmt::print("  seams and panels in {:.2f} s\n", r.seconds);
}

namespace {

json strainJson(const StrainSummary& s) {
  return {{"median", s.median}, {"p95", s.p95}, {"max", s.max}};
}

// Per face of the flattened panel: max(|warp − 1|, |weft − 1|), against the 3D panel as it
// was flattened (scan noise filtered), as flat.json's warp and weft figures are.
std::vector<double> faceStrain(const FlatPanel& fp) {
  const GrainFrames frames = grainFrames(fp.surface, fp.grain);
  const Eigen::MatrixX4d J = grainJacobians(frames, fp.surface.F, fp.uv);
  std::vector<double> out(J.rows());
  for (int f = 0; f < J.rows(); ++f)
    out[f] = std::max(std::abs(Eigen::Vector2d(J(f, 0), J(f, 1)).norm() - 1),
                      std::abs(Eigen::Vector2d(J(f, 2), J(f, 3)).norm() - 1));
  return out;
}

std::string pieceName(const Panel& p) {
  return p.garment + " " + p.name;
}

}  // namespace

Eigen::MatrixX3d remeshedColours(const Scan& scan, const FlatPanel& fp) {
  const int n = static_cast<int>(fp.remeshed.V.rows());
  Eigen::MatrixX3d colour = Eigen::MatrixX3d::Constant(n, 3, 0.75);
  if (scan.colour.rows() != scan.mesh.numVertices()) return colour;
  for (int v = 0; v < n; ++v) {
    colour.row(v).setZero();
    for (int k = 0; k < 3; ++k)
      colour.row(v) += fp.scanBary(v, k) * scan.colour.row(scan.mesh.F(fp.scanFace[v], k));
  }
  return colour;
}

json flatPatternToJson(const PanelsResult& panels, const FlatPatternResult& flat) {
  json out = json::array();
  for (const FlatPanel& fp : flat.panels) {
    const Panel& p = panels.panels[fp.panel];
    json j = {{"name", p.name}, {"garment", p.garment}, {"seconds", fp.seconds}};
    if (!fp.error.empty()) {
      j["error"] = fp.error;
      out.push_back(j);
      continue;
    }
    const FlatteningMetrics& m = fp.metrics;
    double fit = 0;
    for (const FlatEdge& e : fp.edges) fit = std::max(fit, e.fitError);
    j.update({{"grain", {fp.grain.x(), fp.grain.y(), fp.grain.z()}},
              {"area_3d_m2", m.area3d},
              {"area_3d_scan_m2", p.area},
              {"denoise_shift_mm",
               {{"mean", 1e3 * fp.denoiseShiftMean}, {"max", 1e3 * fp.denoiseShiftMax}}},
              {"area_2d_m2", m.area2d},
              {"area_distortion", {{"mean", m.areaDistortionMean}, {"max", m.areaDistortionMax}}},
              {"warp_strain", strainJson(m.warp)},
              {"weft_strain", strainJson(m.weft)},
              {"boundary_length_error", m.boundaryLengthError},
              {"inverted_faces", m.invertedFaces},
              {"boundary_self_intersects", m.boundarySelfIntersects},
              {"refinement_iterations", fp.flattening.iterations},
              {"refinement_reverted", fp.flattening.refinementReverted},
              {"boundary_spikes_pulled_in", fp.flattening.boundarySpikes},
              {"reshaped", fp.reshaped},
              {"strain_as_scanned", fp.reshaped.empty()
                                        ? json(nullptr)
                                        : json{{"warp", strainJson(fp.scannedMetrics.warp)},
                                               {"weft", strainJson(fp.scannedMetrics.weft)}}},
              {"bezier_fit_error_m", fit},
              {"bezier_segments",
               [&] {
                 json a = json::array();
                 for (const FlatEdge& e : fp.edges) a.push_back(e.chain.size());
                 return a;
               }()},
              {"remeshed",
               {{"vertices", fp.remeshed.V.rows()},
                {"faces", fp.remeshed.F.rows()},
                {"min_angle_deg", fp.remeshed.minAngleDeg},
                {"faces_below_angle_bound", fp.remeshed.badFaces},
                {"longest_edge_m", fp.remeshed.longestEdge}}}});
    out.push_back(j);
  }
  json seams = json::array();
  for (const SeamPair& s : flat.seams) {
    const Panel& a = panels.panels[s.panelA];
    const Panel& b = panels.panels[s.panelB];
    seams.push_back(
        {{"a", {{"panel", pieceName(a)}, {"edge", s.edgeA}, {"name", a.edges[s.edgeA].name}}},
         {"b", {{"panel", pieceName(b)}, {"edge", s.edgeB}, {"name", b.edges[s.edgeB].name}}},
         {"length_a_m", s.lengthA},
         {"length_b_m", s.lengthB},
         {"difference_mm", 1000 * std::abs(s.lengthA - s.lengthB)},
         {"vertices_each", s.samples}});
  }
  return {{"panels", out},
          {"stitched_pairs", seams},
          {"warnings", flat.warnings},
          {"seconds", flat.seconds}};
}

void writeFlatPattern(const fs::path& dir, const Scan& scan, const PanelsResult& panels,
                      const FlatPatternResult& flat) {
  fs::create_directories(dir);
  writeJson(dir / "flat.json", flatPatternToJson(panels, flat));
  // The strain picture: the flattened panels (before remeshing), each face by its strain.
  std::vector<SheetPiece> strainPieces, meshPieces;
  std::vector<const FlatPanel*> done;
  const std::vector<Rgb> scale = strainColours();
  constexpr double kStrainMax = 0.10;
  for (const FlatPanel& fp : flat.panels) {
    if (!fp.error.empty()) continue;
    const Panel& p = panels.panels[fp.panel];
    SheetPiece sp;
    sp.label = pieceName(p);
    sp.V = fp.uv;
    sp.F = p.mesh.F;
    for (double s : faceStrain(fp)) sp.faceColour.push_back(colourAt(scale, s / kStrainMax));
    Eigen::MatrixX2d outline(static_cast<int>(fp.remeshed.numBoundaryVertices), 2);
    for (int i = 0; i < fp.remeshed.numBoundaryVertices; ++i) outline.row(i) = fp.remeshed.V.row(i);
    sp.outlines.push_back(outline);
    strainPieces.push_back(std::move(sp));
    done.push_back(&fp);
  }
  writeSheetPng(dir / "pattern_strain.png", strainPieces,
                {"max(|warp - 1|, |weft - 1|) per face", kStrainMax, scale, "%", 100});
  // panels_flat.obj: the remeshed panels where the strain picture lays them out, z = 0.
  const Eigen::MatrixX2d offset = layoutPieces(strainPieces);
  int nV = 0, nF = 0;
  for (const FlatPanel* fp : done) {
    nV += static_cast<int>(fp->remeshed.V.rows());
    nF += static_cast<int>(fp->remeshed.F.rows());
  }
  if (nF == 0) return;
  TriMesh all;
  all.V.resize(nV, 3);
  all.F.resize(nF, 3);
  Eigen::MatrixX3d colour(nV, 3);
  Eigen::VectorXi group(nF);
  std::vector<std::string> names;
  const bool texture = scan.texture.has_value();
  Eigen::MatrixX2d UV(texture ? nV : 0, 2);
  int v0 = 0, f0 = 0;
  for (size_t i = 0; i < done.size(); ++i) {
    const FlatPanel& fp = *done[i];
    for (int v = 0; v < fp.remeshed.V.rows(); ++v) {
      const Eigen::Vector2d q =
          fp.remeshed.V.row(v).transpose() + offset.row(static_cast<int>(i)).transpose();
      all.V.row(v0 + v) << q.x(), q.y(), 0;
      const int f = fp.scanFace[v];
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      for (int k = 0; k < 3; ++k)
        if (texture)
          uv += fp.scanBary(v, k) * scan.texture->UV.row(scan.texture->FUV(f, k)).transpose();
      if (texture) UV.row(v0 + v) = uv.transpose();
    }
    colour.middleRows(v0, fp.remeshed.V.rows()) = remeshedColours(scan, fp);
    for (int f = 0; f < fp.remeshed.F.rows(); ++f) {
      all.F.row(f0 + f) = fp.remeshed.F.row(f).array() + v0;
      group[f0 + f] = static_cast<int>(i);
    }
    const Panel& p = panels.panels[fp.panel];
    names.push_back(p.garment + "_" + p.name);
    v0 += static_cast<int>(fp.remeshed.V.rows());
    f0 += static_cast<int>(fp.remeshed.F.rows());
  }
  if (texture) {
    Texture t = *scan.texture;
    t.UV = UV;
    t.FUV = all.F;
    writeObjTextured(dir / "panels_flat.obj", all, t);
  } else {
    MeshAttributes attrs;
    attrs.faceGroups = &group;
    attrs.groupNames = &names;
    if (colour.rows() == all.numVertices() && scan.colour.rows() > 0) attrs.colour = &colour;
    writeObj(dir / "panels_flat.obj", all, attrs);
  }
}

void printFlatPattern(const PanelsResult& panels, const FlatPatternResult& flat) {
  int ok = 0;
  double worstP95 = 0, worstPair = 0, minAngle = 180;
  for (const FlatPanel& fp : flat.panels) {
    if (!fp.error.empty()) continue;
    ++ok;
    worstP95 = std::max({worstP95, fp.metrics.warp.p95, fp.metrics.weft.p95});
    minAngle = std::min(minAngle, fp.remeshed.minAngleDeg);
  }
  for (const SeamPair& s : flat.seams)
    if (flat.panels[s.panelA].error.empty() && flat.panels[s.panelB].error.empty())
      worstPair = std::max(worstPair, std::abs(s.lengthA - s.lengthB));
  fmt::print(
      "flattened {} of {} panels in {:.2f} s: warp/weft strain p95 ≤ {:.1f} %, stitched "
      "pairs of flattened panels within {:.1f} mm, remeshed min angle {:.1f}°\n",
      ok, panels.panels.size(), flat.seconds, 100 * worstP95, 1000 * worstPair, minAngle);
  for (const FlatPanel& fp : flat.panels)
    if (!fp.reshaped.empty() && fp.error.empty())
      fmt::print(
          "  panel '{}' of {} flattened with its {}: warp/weft strain p95 {:.1f} % (against "
          "the bent panel as scanned {:.1f} %)\n",
          panels.panels[fp.panel].name, panels.panels[fp.panel].garment, fp.reshaped,
          100 * std::max(fp.metrics.warp.p95, fp.metrics.weft.p95),
          100 * std::max(fp.scannedMetrics.warp.p95, fp.scannedMetrics.weft.p95));
  for (const std::string& w : flat.warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace s2p::app
