#include "app/pattern_output.h"

#include <fmt/format.h>

#include "app/commands.h"
#include "export/png.h"
#include "export/preview.h"
#include "io/write_mesh.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

Eigen::Vector3d toFrame(const Eigen::Affine3d& t, const Eigen::Vector3d& p) { return t * p; }

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
    case 0: r = 1, g = x; break;
    case 1: r = x, g = 1; break;
    case 2: g = 1, b = x; break;
    case 3: g = x, b = 1; break;
    case 4: r = x, b = 1; break;
    default: r = 1, b = x; break;
  }
  const auto c = [](double v) { return static_cast<std::uint8_t>(60 + 170 * v); };
  return {c(r), c(g), c(b)};
}

}  // namespace

PanelsInput panelsInput(const Segmentation& segmentation, const PosedFeatures& body) {
  PanelsInput in;
  for (const GarmentPiece& g : segmentation.garments) {
    GarmentKind kind = GarmentKind::Upper;
    if (g.name == "onepiece" || segmentation.layout == GarmentLayout::OnePiece)
      kind = GarmentKind::OnePiece;
    else if (g.label == Label::Lower)
      kind = GarmentKind::Lower;
    in.garments.push_back({g.name, kind, g.mesh, g.faceOrigin});
  }
  in.body = body.body;
  in.features = body.features;
  in.canonical = body.canonical;
  return in;
}

json panelsToJson(const PanelsResult& r, const Eigen::Affine3d& toInput) {
  json garments = json::array();
  for (const GarmentPanels& g : r.garments) {
    json panels = json::array(), openings = json::array(), seams = json::array();
    for (int p : g.panels) panels.push_back(r.panels[p].name);
    for (const Opening& o : g.openings)
      openings.push_back({{"name", o.name}, {"limb", toString(o.limb)}, {"place_on_limb", o.t},
                          {"length_m", o.length}, {"centroid", point(toInput, o.centroid)}});
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
                       {"sign_points", s.signs},
                       {"dropped_sign_points", s.droppedSigns},
                       {"dropped_with_their_pair", s.pairedDrops},
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
      json j = {{"name", edge.name},
                {"kind", edge.opening ? "opening" : "seam"},
                {"from_corner", e},
                {"to_corner", (e + 1) % p.edges.size()},
                {"length_m", edge.length},
                {"vertices", edge.vertices.size()}};
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
    meshes[i] = r.panels[i].mesh;
    scene.meshes.push_back({&meshes[i], nullptr, panelColour(static_cast<int>(i))});
    for (const PanelEdge& e : r.panels[i].edges) {
      if (e.opening) continue;
      Eigen::MatrixX3d P(static_cast<int>(e.vertices.size()), 3);
      for (size_t k = 0; k < e.vertices.size(); ++k)
        P.row(static_cast<int>(k)) = r.panels[i].mesh.V.row(e.vertices[k]);
      scene.lines.push_back({P, e.name == "cut" ? Rgb{200, 0, 200} : Rgb{20, 20, 20}, 2.5f, false,
                             false});
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

}  // namespace s2p::app
