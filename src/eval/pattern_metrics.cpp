#include "eval/pattern_metrics.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "core/mesh_topology.h"
#include "pattern/panel_denoise.h"

namespace s2p {

namespace {

using Vec3 = Eigen::Vector3d;

double maxAbs(const std::vector<std::pair<std::string, double>>& v) {
  double m = 0;
  for (const auto& [name, x] : v) m = std::max(m, std::abs(x));
  return m;
}

bool isDisk(const TriMesh& m) {
  const MeshTopology t(m.F, m.numVertices());
  return t.boundaryLoops().size() == 1 && t.eulerCharacteristic() == 1;
}

const Panel* panelNamed(const PanelsResult& r, const GarmentPanels& g, const std::string& name) {
  for (int p : g.panels)
    if (r.panels[p].name == name) return &r.panels[p];
  return nullptr;
}

// A panel's area with the scanner's noise taken out as the pattern stage takes it out before
// flattening (its corners fixed).
double clothArea(const Panel& panel) {
  std::vector<int> corners;
  for (const PanelEdge& e : panel.edges) corners.push_back(e.vertices.front());
  return surfaceArea(denoisePanel(panel.mesh, panel.loop, corners));
}

// The normal of the coronal plane of the limb nearest p: on a leg the plane through its hip and
// ankle that holds the body's left-right axis; elsewhere the body's own (normal: front).
Vec3 limbCoronalNormal(const BodyFrame& frame, const Vec3& p) {
  const Limb limb = frame.nearestLimb(p).limb;
  if (!isLeg(limb)) return frame.front();
  const bool left = limb == Limb::LeftLeg;
  const Vec3 axis = frame.at(left ? Canonical::LeftAnkle : Canonical::RightAnkle) -
                    frame.at(left ? Canonical::LeftHip : Canonical::RightHip);
  const Vec3 n = frame.left().cross(axis);
  return n.norm() > 1e-9 ? Vec3(n.normalized()) : frame.front();
}

}  // namespace

double PatternScore::maxMirrorAreaDiff() const { return maxAbs(mirrorAreaDiff); }
double PatternScore::maxMirrorClothAreaDiff() const { return maxAbs(mirrorClothAreaDiff); }
double PatternScore::maxSideSeamLimbAngle() const { return maxAbs(sideSeamLimbAngle); }
double PatternScore::maxArmholeToArmpit() const { return maxAbs(armholeToArmpit); }
double PatternScore::maxSideSeamAngle() const { return maxAbs(sideSeamAngle); }

PatternScore scorePattern(const PanelsResult& r, const Truth& truth, const TriMesh& body,
                          const Eigen::MatrixX3d& canonical) {
  PatternScore s;
  const BodyFrame frame(canonical);
  // Garment types and panel sets.
  for (const TrueGarment& tg : truth.garments) {
    if (tg.patternType.empty()) continue;
    // Only the outermost garment of a label makes a pattern: the largest visible one.
    bool outermost = true;
    for (const TrueGarment& o : truth.garments)
      if (&o != &tg && !o.patternType.empty() && o.label == tg.label && o.visibleArea > tg.visibleArea)
        outermost = false;
    if (!outermost) continue;
    GarmentPatternScore gs;
    gs.truthGarment = tg.name;
    gs.expectedType = tg.patternType;
    gs.expectedPanels = tg.panels;
    std::sort(gs.expectedPanels.begin(), gs.expectedPanels.end());
    for (const GarmentPanels& g : r.garments) {
      const bool match = tg.onePiece ? g.kind == GarmentKind::OnePiece
                                     : (tg.label == Label::Upper ? g.kind == GarmentKind::Upper
                                                                 : g.kind == GarmentKind::Lower);
      if (!match) continue;
      gs.predictedGarment = g.name;
      gs.foundType = g.type;
      for (int p : g.panels) gs.foundPanels.push_back(r.panels[p].name);
      std::sort(gs.foundPanels.begin(), gs.foundPanels.end());
    }
    gs.typeOk = gs.foundType == gs.expectedType;
    gs.panelsOk = gs.foundPanels == gs.expectedPanels;
    s.allTypesOk &= gs.typeOk;
    s.allPanelsOk &= gs.panelsOk;
    s.garments.push_back(std::move(gs));
  }
  // Topology and partners.
  for (size_t p = 0; p < r.panels.size(); ++p) {
    const Panel& panel = r.panels[p];
    ++s.panels;
    s.disks += isDisk(panel.mesh);
    for (const PanelEdge& e : panel.edges) {
      if (e.opening) continue;
      ++s.seamEdges;
      if (e.partnerPanel < 0 || e.partnerEdge < 0) {
        ++s.unpartnered;
        continue;
      }
      const PanelEdge& t = r.panels[e.partnerPanel].edges[e.partnerEdge];
      const bool back = t.partnerPanel == static_cast<int>(p) &&
                        &r.panels[t.partnerPanel].edges[t.partnerEdge] == &e;
      if (!back) ++s.unpartnered;
      s.maxPartnerMismatch = std::max(
          s.maxPartnerMismatch, std::abs(e.length - t.length) / std::max(e.length, t.length));
    }
  }
  // Mirrored panels.
  for (const GarmentPanels& g : r.garments)
    for (const char* base : {"sleeve", "front", "back"}) {
      const Panel* a = panelNamed(r, g, std::string("left_") + base);
      const Panel* b = panelNamed(r, g, std::string("right_") + base);
      if (!a || !b) continue;
      s.mirrorAreaDiff.push_back({g.name + ":" + base,
                                  std::abs(a->area - b->area) / std::max(a->area, b->area)});
      const double ca = clothArea(*a), cb = clothArea(*b);
      s.mirrorClothAreaDiff.push_back({g.name + ":" + base, std::abs(ca - cb) / std::max(ca, cb)});
    }
  // Armholes against the armpit; side seams against the coronal plane.
  const double armpit[2] = {armpitHeight(body, frame, true), armpitHeight(body, frame, false)};
  for (const GarmentPanels& g : r.garments) {
    std::map<std::string, double> lowest;
    for (int p : g.panels) {
      const Panel& panel = r.panels[p];
      for (const PanelEdge& e : panel.edges) {
        if (e.opening) continue;
        const bool armhole = e.name.find("_armhole") != std::string::npos;
        if (armhole) {
          double& low = lowest.try_emplace(e.name, std::numeric_limits<double>::infinity()).first->second;
          for (int v : e.vertices) low = std::min(low, frame.height(panel.mesh.V.row(v).transpose()));
        }
        if (e.name.size() > 5 && e.name.compare(e.name.size() - 5, 5, "_side") == 0 &&
            p < e.partnerPanel && e.vertices.size() >= 3) {
          Eigen::MatrixX3d P(static_cast<int>(e.vertices.size()), 3);
          for (size_t k = 0; k < e.vertices.size(); ++k)
            P.row(static_cast<int>(k)) = panel.mesh.V.row(e.vertices[k]);
          const Eigen::RowVector3d mean = P.colwise().mean();
          const Eigen::MatrixX3d Q = P.rowwise() - mean;
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Q.transpose() * Q);
          const Vec3 dir = es.eigenvectors().col(2);
          const double angle = std::asin(std::min(1.0, std::abs(dir.dot(frame.front())))) * 180 / M_PI;
          s.sideSeamAngle.push_back({g.name + ":" + panel.name + ":" + e.name, angle});
          const Vec3 normal = limbCoronalNormal(frame, mean.transpose());
          const double limbAngle = std::asin(std::min(1.0, std::abs(dir.dot(normal)))) * 180 / M_PI;
          s.sideSeamLimbAngle.push_back({g.name + ":" + panel.name + ":" + e.name, limbAngle});
        }
      }
    }
    for (const auto& [name, low] : lowest) {
      const double a = armpit[name.rfind("left", 0) == 0 ? 0 : 1];
      if (std::isfinite(a) && std::isfinite(low)) s.armholeToArmpit.push_back({g.name + ":" + name, low - a});
    }
  }
  return s;
}

}  // namespace s2p
