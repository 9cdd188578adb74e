#include "app/pattern_files.h"

#include <fmt/format.h>

#include <cmath>
#include <ctime>
#include <map>

#include "app/commands.h"
#include "app/pattern_output.h"
#include "export/pattern_dxf.h"
#include "export/pattern_sheet.h"
#include "io/write_mesh.h"
#include "pattern/garmentcode.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {

namespace {

// panels.obj's first vertex of every flattened panel (−1: not in the file); the same order as
// panels_flat.obj (writeFlatPattern).
std::vector<int> vertexOffsets(const FlatPatternResult& flat) {
  std::vector<int> offset(flat.panels.size(), -1);
  int n = 0;
  for (size_t p = 0; p < flat.panels.size(); ++p)
    if (flat.panels[p].error.empty()) {
      offset[p] = n;
      n += static_cast<int>(flat.panels[p].remeshed.V.rows());
    }
  return offset;
}

// The point of an edge's remeshed vertex chain at arc-length fraction f, with the outward
// normal there (the panel is counter-clockwise: outward is the tangent turned clockwise).
SewingNotch notchAt(const FlatPanel& fp, int edge, double f) {
  const std::vector<int>& ids = fp.edges[edge].vertices;
  std::vector<double> run{0.0};
  for (size_t k = 0; k + 1 < ids.size(); ++k)
    run.push_back(run.back() + (fp.remeshed.V.row(ids[k + 1]) - fp.remeshed.V.row(ids[k])).norm());
  const double s = f * run.back();
  size_t k = 0;
  while (k + 2 < run.size() && run[k + 1] < s) ++k;
  const Eigen::Vector2d a = fp.remeshed.V.row(ids[k]).transpose();
  const Eigen::Vector2d b = fp.remeshed.V.row(ids[k + 1]).transpose();
  const double len = run[k + 1] - run[k];
  const double t = len > 0 ? (s - run[k]) / len : 0.0;
  const Eigen::Vector2d d = (b - a).normalized();
  return {a + t * (b - a), Eigen::Vector2d(d.y(), -d.x())};
}

// Fractions along a stitch where the notches go: the middle, and the thirds on a long seam.
std::vector<double> notchFractions(double length) {
  if (length > 0.40) return {1.0 / 3.0, 2.0 / 3.0};
  return {0.5};
}

Rgb toRgb(const Eigen::Vector3d& c) {
  const auto byte = [](double v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0, 1.0) * 255 + 0.5); };
  return {byte(c.x()), byte(c.y()), byte(c.z())};
}

// Today as YYYY-MM-DD (UTC), the pattern's creation date.
std::string currentDate() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
  return buf;
}

bool isLeft(const std::string& name) { return name.rfind("left_", 0) == 0; }

}  // namespace

SewingPattern sewingPattern(const PatternResult& pattern, const std::string& date) {
  const PanelsResult& panels = pattern.panels;
  const FlatPatternResult& flat = pattern.flat;
  SewingPattern out;
  out.creationDate = date;
  // Notches per (panel, edge): each stitch's fractions on A, mirrored on B.
  std::map<int, std::vector<SewingNotch>> notches;
  for (const Stitch& s : pattern.stitches.stitches)
    for (double f : notchFractions(std::max(s.lengthA, s.lengthB))) {
      notches[s.panelA].push_back(notchAt(flat.panels[s.panelA], s.edgeA, f));
      notches[s.panelB].push_back(notchAt(flat.panels[s.panelB], s.edgeB, 1.0 - f));
    }
  // Symmetric pairs: left_X and right_X of one garment, both flattened.
  auto flattened = [&](int p) { return flat.panels[p].error.empty(); };
  std::map<std::pair<int, std::string>, int> byName;
  for (size_t p = 0; p < panels.panels.size(); ++p)
    byName[{panels.panels[p].garmentIndex, panels.panels[p].name}] = static_cast<int>(p);
  for (size_t p = 0; p < panels.panels.size(); ++p) {
    const Panel& panel = panels.panels[p];
    if (!flattened(static_cast<int>(p))) continue;
    SewingPiece piece;
    piece.name = panel.name;
    piece.garment = panels.garments[panel.garmentIndex].type.empty()
                        ? panel.garment
                        : panels.garments[panel.garmentIndex].type;
    const std::string base = panel.name.substr(panel.name.find('_') + 1);
    if (isLeft(panel.name) || panel.name.rfind("right_", 0) == 0) {
      const auto partner = byName.find(
          {panel.garmentIndex, (isLeft(panel.name) ? "right_" : "left_") + base});
      if (partner != byName.end() && flattened(partner->second)) {
        if (!isLeft(panel.name)) continue;  // drawn once, as the left piece
        piece.name = base;
        piece.quantity = 2;
        piece.mirrored = true;
      }
    }
    const FlatPanel& fp = flat.panels[p];
    // The sew line: the Bézier chains sampled every ≤ 3 mm (chord error well below 1 mm).
    for (const FlatEdge& e : fp.edges) {
      piece.corners.push_back(static_cast<int>(piece.sewLine.size()));
      const int count = std::max(2, static_cast<int>(std::ceil(e.chain.length() / 0.003)) + 1);
      const Eigen::MatrixX2d pts = resampleChain(e.chain, count);
      for (int i = 0; i + 1 < pts.rows(); ++i) piece.sewLine.push_back(pts.row(i).transpose());
    }
    // Corner notches where a seam begins (panels meet there), then the stitches'.
    for (size_t e = 0; e < fp.edges.size(); ++e)
      if (!panel.edges[e].opening) piece.notches.push_back(notchAt(fp, static_cast<int>(e), 0.0));
    for (const SewingNotch& n : notches[static_cast<int>(p)]) piece.notches.push_back(n);
    const Eigen::Vector2d lo = fp.remeshed.V.colwise().minCoeff(), hi = fp.remeshed.V.colwise().maxCoeff();
    const Eigen::Vector2d mid = 0.5 * (lo + hi);
    const double half = 0.3 * (hi.y() - lo.y());
    piece.grainFrom = mid - Eigen::Vector2d(0, half);
    piece.grainTo = mid + Eigen::Vector2d(0, half);
    out.pieces.push_back(std::move(piece));
  }
  return out;
}

json stitchesToJson(const PatternResult& pattern) {
  const std::vector<int> offset = vertexOffsets(pattern.flat);
  json stitches = json::array();
  for (const Stitch& s : pattern.stitches.stitches) {
    const Panel& a = pattern.panels.panels[s.panelA];
    const Panel& b = pattern.panels.panels[s.panelB];
    json pairs = json::array();
    for (const auto& [va, vb] : s.vertices)
      pairs.push_back({offset[s.panelA] + va, offset[s.panelB] + vb});
    stitches.push_back({{"name", s.name},
                        {"a", {{"panel", a.garment + "_" + a.name}, {"edge", s.edgeA}}},
                        {"b", {{"panel", b.garment + "_" + b.name}, {"edge", s.edgeB}}},
                        {"length_a_m", s.lengthA},
                        {"length_b_m", s.lengthB},
                        {"mismatch_mm", 1000 * s.mismatch()},
                        {"scan_gap_mm", 1000 * s.scanGap},
                        {"rest_gap_mm", 1000 * s.restGap},
                        {"vertex_pairs", pairs}});
  }
  return {{"units", "m"},
          {"mesh", "panels.obj (and panels_flat.obj: same vertices in the same order)"},
          {"indices", "0-based vertex ids into panels.obj"},
          {"orientation", "edge A runs opposite edge B: right sides meet"},
          {"stitches", stitches},
          {"warnings", pattern.stitches.warnings}};
}

json placementToJson(const PatternResult& pattern) {
  const Placement& pl = pattern.placement;
  json panels = json::array();
  for (size_t p = 0; p < pl.panels.size(); ++p) {
    const PlacedPanel& pp = pl.panels[p];
    if (!pp.placed) continue;
    const Panel& panel = pattern.panels.panels[p];
    panels.push_back({{"panel", panel.garment + "_" + panel.name},
                      {"joint", toString(pp.joint)},
                      {"offset_m", pp.offset},
                      {"distance_to_part_m", pp.distanceToPart},
                      {"clearance_m", pp.clearance},
                      {"normal", {pp.R(0, 2), pp.R(1, 2), pp.R(2, 2)}}});
  }
  double worst = 0;
  for (const Stitch& s : pattern.stitches.stitches) worst = std::max(worst, s.mismatch());
  return {{"pose", pl.pose},
          {"panels", panels},
          {"stitches", pattern.stitches.stitches.size()},
          {"max_stitch_mismatch_mm", 1000 * worst},
          {"warnings", pl.warnings},
          {"seconds", pl.seconds}};
}

void writePatternFiles(const fs::path& dir, const Scan& scan, const PatternResult& pattern,
                       const PrintOptions& print) {
  fs::create_directories(dir);
  const PanelsResult& panels = pattern.panels;
  const FlatPatternResult& flat = pattern.flat;
  const bool placed = !pattern.placement.panels.empty();
  if (placed) {
    writeJson(dir / "pattern.json",
              garmentCodeSpecification(panels, flat, pattern.placement, pattern.stitches));
    writeObj(dir / "body_rest.obj", pattern.placement.restBody);
    if (pattern.placement.underBody.numFaces() > 0)
      writeObj(dir / "body_under.obj", pattern.placement.underBody);
  }
  writeJson(dir / "stitches.json", stitchesToJson(pattern));
  // panels.obj: the placed panels (the flat layout if there is no placement), one group each.
  std::vector<SheetPiece> sheet;
  TriMesh all;
  std::vector<Eigen::MatrixX3d> Vs, colours;
  std::vector<Eigen::MatrixX3i> Fs;
  std::vector<std::string> names;
  for (size_t p = 0; p < flat.panels.size(); ++p) {
    const FlatPanel& fp = flat.panels[p];
    if (!fp.error.empty()) continue;
    const Panel& panel = panels.panels[p];
    Eigen::MatrixX3d V(fp.remeshed.V.rows(), 3);
    if (placed && pattern.placement.panels[p].placed)
      V = pattern.placement.panels[p].V;
    else
      V << fp.remeshed.V, Eigen::VectorXd::Zero(fp.remeshed.V.rows());
    Vs.push_back(V);
    Fs.push_back(fp.remeshed.F);
    colours.push_back(remeshedColours(scan, fp));
    names.push_back(panel.garment + "_" + panel.name);
    // pattern.png: the piece in the scan's colours, named.
    SheetPiece sp;
    sp.label = panel.garment + " " + panel.name;
    sp.V = fp.remeshed.V;
    sp.F = fp.remeshed.F;
    for (int f = 0; f < fp.remeshed.F.rows(); ++f) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) c += colours.back().row(fp.remeshed.F(f, k)).transpose() / 3.0;
      sp.faceColour.push_back(toRgb(c));
    }
    Eigen::MatrixX2d outline(fp.remeshed.numBoundaryVertices, 2);
    for (int i = 0; i < fp.remeshed.numBoundaryVertices; ++i) outline.row(i) = fp.remeshed.V.row(i);
    sp.outlines.push_back(outline);
    sheet.push_back(std::move(sp));
  }
  if (Vs.empty()) return;
  int nV = 0, nF = 0;
  for (size_t i = 0; i < Vs.size(); ++i) nV += Vs[i].rows(), nF += Fs[i].rows();
  all.V.resize(nV, 3);
  all.F.resize(nF, 3);
  Eigen::MatrixX3d colour(nV, 3);
  Eigen::VectorXi group(nF);
  for (int i = 0, v0 = 0, f0 = 0; i < static_cast<int>(Vs.size()); ++i) {
    all.V.middleRows(v0, Vs[i].rows()) = Vs[i];
    colour.middleRows(v0, Vs[i].rows()) = colours[i];
    all.F.middleRows(f0, Fs[i].rows()) = Fs[i].array() + v0;
    group.segment(f0, Fs[i].rows()).setConstant(i);
    v0 += static_cast<int>(Vs[i].rows());
    f0 += static_cast<int>(Fs[i].rows());
  }
  MeshAttributes attrs;
  attrs.faceGroups = &group;
  attrs.groupNames = &names;
  if (scan.colour.rows() > 0) attrs.colour = &colour;
  writeObj(dir / "panels.obj", all, attrs);
  writeSheetPng(dir / "pattern.png", sheet, {"", 0, {}, "", 1});
  const SewingPattern sewing = sewingPattern(pattern, currentDate());
  writePatternSvg(dir / "pattern.svg", sewing, print);
  writePatternPdf(dir / "pattern.pdf", sewing, print);
  writePatternDxf(dir / "pattern.dxf", sewing, {print.seamAllowance});
}

void printPatternFiles(const PatternResult& pattern) {
  const Placement& pl = pattern.placement;
  int placed = 0;
  double far = 0, least = std::numeric_limits<double>::infinity();
  for (const PlacedPanel& pp : pl.panels)
    if (pp.placed) {
      ++placed;
      far = std::max(far, pp.distanceToPart);
      least = std::min(least, pp.clearance);
    }
  double worst = 0;
  for (const Stitch& s : pattern.stitches.stitches) worst = std::max(worst, s.mismatch());
  if (placed > 0)
    fmt::print("placed {} panels around the rest body ({}): clear of it by ≥ {:.1f} cm, at most "
               "{:.1f} cm from their parts on average\n",
               placed, pl.pose, 100 * least, 100 * far);
  fmt::print("{} stitches, the two sides of each within {:.2f} mm\n",
             pattern.stitches.stitches.size(), 1000 * worst);
  for (const std::string& w : pl.warnings) fmt::print("  warning: {}\n", w);
  for (const std::string& w : pattern.stitches.warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace s2p::app
