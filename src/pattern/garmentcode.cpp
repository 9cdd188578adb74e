#include "pattern/garmentcode.h"

#include <cmath>
#include <map>
#include <numbers>

namespace s2p {

namespace {

using nlohmann::json;
constexpr double kCm = 100.0;  // GarmentCode's units_in_meter

json cm(const Eigen::Vector2d& p) { return json::array({kCm * p.x(), kCm * p.y()}); }

// A control point c of the edge start → end in GarmentCode's relative coordinates: c = start +
// u·d + v·perp(d), d = end − start, perp(d) = (−d_y, d_x).
json relative(const Eigen::Vector2d& start, const Eigen::Vector2d& end, const Eigen::Vector2d& c) {
  const Eigen::Vector2d d = end - start, perp(-d.y(), d.x());
  const double dd = d.squaredNorm();
  return json::array({(c - start).dot(d) / dd, (c - start).dot(perp) / dd});
}

// A segment whose control points lie within this fraction of its chord from the chord is
// written as GarmentCode's straight edge.
constexpr double kStraight = 1e-4;

bool isStraight(const CubicBezier& b) {
  const Eigen::Vector2d d = b.p[3] - b.p[0];
  const double l = d.norm();
  if (l == 0.0) return true;
  auto off = [&](const Eigen::Vector2d& c) {
    return std::abs(d.x() * (c - b.p[0]).y() - d.y() * (c - b.p[0]).x()) / l;
  };
  const double u1 = (b.p[1] - b.p[0]).dot(d) / (l * l), u2 = (b.p[2] - b.p[0]).dot(d) / (l * l);
  return off(b.p[1]) < kStraight * l && off(b.p[2]) < kStraight * l && u1 >= 0 && u2 <= 1;
}

}  // namespace

std::string garmentCodePanelName(const Panel& panel) { return panel.garment + "_" + panel.name; }

Eigen::Vector3d eulerXyzDegrees(const Eigen::Matrix3d& R) {
  // R = Rz(γ)·Ry(β)·Rx(α): R(2,0) = −sin β, R(2,1) = cos β sin α, R(1,0) = sin γ cos β.
  const double beta = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  double alpha, gamma;
  if (std::abs(R(2, 0)) < 1.0 - 1e-12) {
    alpha = std::atan2(R(2, 1), R(2, 2));
    gamma = std::atan2(R(1, 0), R(0, 0));
  } else {  // gimbal lock: only α − γ (or α + γ) is determined; take γ = 0
    alpha = std::atan2(-R(1, 2), R(1, 1));
    gamma = 0.0;
  }
  return Eigen::Vector3d(alpha, beta, gamma) * 180.0 / std::numbers::pi;
}

json garmentCodeSpecification(const PanelsResult& panels, const FlatPatternResult& flat,
                              const Placement& placement, const StitchSet& stitches) {
  const size_t nP = panels.panels.size();
  auto placed = [&](int p) { return placement.panels[p].placed; };
  // Every seam edge cut at its partner's breaks, mirrored (the partner runs the other way).
  std::vector<std::vector<BezierChain>> chains(nP);
  for (size_t p = 0; p < nP; ++p)
    if (placed(static_cast<int>(p)))
      for (const FlatEdge& e : flat.panels[p].edges) chains[p].push_back(e.chain);
  for (const Stitch& s : stitches.stitches) {
    if (!placed(s.panelA) || !placed(s.panelB)) continue;
    const BezierChain a = flat.panels[s.panelA].edges[s.edgeA].chain;
    const BezierChain b = flat.panels[s.panelB].edges[s.edgeB].chain;
    auto mirrored = [](std::vector<double> f) {
      for (double& x : f) x = 1.0 - x;
      return f;
    };
    std::vector<double> fa = jointFractions(a), fb = mirrored(jointFractions(b));
    std::vector<double> all = fa;
    all.insert(all.end(), fb.begin(), fb.end());
    chains[s.panelA][s.edgeA] = splitChainAt(a, all);
    chains[s.panelB][s.edgeB] = splitChainAt(b, mirrored(all));
  }

  json panelsJson = json::object(), order = json::array();
  // (panel, edge) → its first GarmentCode edge and how many there are.
  std::map<std::pair<int, int>, std::pair<int, int>> edgeRange;
  for (size_t p = 0; p < nP; ++p) {
    if (!placed(static_cast<int>(p))) continue;
    const PlacedPanel& pp = placement.panels[p];
    json vertices = json::array(), edges = json::array();
    int index = 0, count = 0;
    for (const BezierChain& c : chains[p]) count += c.size();
    for (size_t e = 0; e < chains[p].size(); ++e) {
      edgeRange[{static_cast<int>(p), static_cast<int>(e)}] = {index, chains[p][e].size()};
      for (const CubicBezier& b : chains[p][e].segments) {
        vertices.push_back(cm(b.p[0]));
        json edge = {{"endpoints", json::array({index, (index + 1) % count})}};
        if (!isStraight(b))
          edge["curvature"] = {{"type", "cubic"},
                               {"params", json::array({relative(b.p[0], b.p[3], b.p[1]),
                                                       relative(b.p[0], b.p[3], b.p[2])})}};
        edges.push_back(std::move(edge));
        ++index;
      }
    }
    const Eigen::Vector3d euler = eulerXyzDegrees(pp.R);
    const std::string name = garmentCodePanelName(panels.panels[p]);
    panelsJson[name] = {{"translation", json::array({kCm * pp.t.x(), kCm * pp.t.y(), kCm * pp.t.z()})},
                        {"rotation", json::array({euler.x(), euler.y(), euler.z()})},
                        {"vertices", vertices},
                        {"edges", edges}};
    order.push_back(name);
  }
  json stitchesJson = json::array();
  for (const Stitch& s : stitches.stitches) {
    if (!placed(s.panelA) || !placed(s.panelB)) continue;
    const auto [a0, na] = edgeRange.at({s.panelA, s.edgeA});
    const auto [b0, nb] = edgeRange.at({s.panelB, s.edgeB});
    if (na != nb) continue;  // splitChainAt merges the same breaks on both sides
    const std::string pa = garmentCodePanelName(panels.panels[s.panelA]);
    const std::string pb = garmentCodePanelName(panels.panels[s.panelB]);
    for (int k = 0; k < na; ++k)
      stitchesJson.push_back(json::array(
          {{{"panel", pa}, {"edge", a0 + k}}, {{"panel", pb}, {"edge", b0 + (nb - 1 - k)}}}));
  }
  return {{"pattern", {{"panels", panelsJson}, {"stitches", stitchesJson}, {"panel_order", order}}},
          {"parameters", json::object()},
          {"parameter_order", json::array()},
          {"properties",
           {{"curvature_coords", "relative"},
            {"normalize_panel_translation", false},
            {"normalized_edge_loops", true},
            {"units_in_meter", 100}}}};
}

}  // namespace s2p
