#include "pattern/flat_pattern.h"

#include <fmt/format.h>

#include <chrono>
#include <map>

#include "core/error.h"
#include "pattern/uv_locator.h"

namespace s2p {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Eigen::MatrixX2d rowsOf(const Eigen::MatrixX2d& uv, const std::vector<int>& ids) {
  Eigen::MatrixX2d P(static_cast<int>(ids.size()), 2);
  for (size_t i = 0; i < ids.size(); ++i) P.row(static_cast<int>(i)) = uv.row(ids[i]);
  return P;
}

// Flattening and Bézier outline of one panel (no remeshing yet: the sample counts depend on the
// partner panels' 2D lengths).
void flattenAndOutline(const Panel& panel, const BodyFrame& frame,
                       const FlatPatternOptions& options, FlatPanel& out) {
  out.grain = panelGrain(panel, frame);
  const std::string name = panel.garment + " " + panel.name;
  out.flattening = flattenPanel(panel.mesh, out.grain, name, options.flatten);
  out.uv = out.flattening.uv;
  out.metrics = flatteningMetrics(panel.mesh, out.uv, out.grain);
  for (const PanelEdge& e : panel.edges) {
    FlatEdge fe;
    const Eigen::MatrixX2d poly = rowsOf(out.uv, e.vertices);
    for (int i = 0; i + 1 < poly.rows(); ++i) fe.length2d += (poly.row(i + 1) - poly.row(i)).norm();
    fe.chain = fitBezierChain(poly, options.bezier);
    fe.fitError = maxDeviation(fe.chain, poly);
    out.edges.push_back(std::move(fe));
  }
}

void remesh(const Panel& panel, const TriMesh& scan, const std::vector<int>& counts,
            const FlatPatternOptions& options, FlatPanel& out) {
  std::vector<Eigen::MatrixX2d> samples;
  for (size_t e = 0; e < out.edges.size(); ++e)
    samples.push_back(resampleChain(out.edges[e].chain, counts[e]));
  out.remeshed = remeshPanel(samples, panel.garment + " " + panel.name, options.remesh);
  for (size_t e = 0; e < out.edges.size(); ++e) out.edges[e].vertices = out.remeshed.edgeVertices[e];
  const UvLocator locator(out.uv, panel.mesh.F);
  out.location = locator.locate(out.remeshed.V);
  out.position = interpolateAt(out.location, panel.mesh.F, panel.mesh.V);
  const int n = static_cast<int>(out.location.size());
  out.scanFace.resize(n);
  out.scanBary.resize(n, 3);
  for (int v = 0; v < n; ++v) {
    const int f = panel.faceOrigin[out.location[v].face];
    out.scanFace[v] = f;
    const Eigen::Vector3d p = out.position.row(v).transpose();
    out.scanBary.row(v) =
        closestPointBarycentric(p, scan.V.row(scan.F(f, 0)).transpose(),
                                scan.V.row(scan.F(f, 1)).transpose(),
                                scan.V.row(scan.F(f, 2)).transpose())
            .transpose();
  }
}

}  // namespace

Eigen::Vector3d panelGrain(const Panel& panel, const BodyFrame& frame) {
  if (panel.name.find("sleeve") != std::string::npos) {
    const bool left = panel.name.rfind("left", 0) == 0;
    const Eigen::Vector3d axis =
        frame.at(left ? Canonical::LeftShoulder : Canonical::RightShoulder) -
        frame.at(left ? Canonical::LeftWrist : Canonical::RightWrist);
    if (axis.norm() > 1e-6) return axis.normalized();
  }
  return frame.up();
}

FlatPatternResult runFlatPattern(const PanelsResult& panels, const TriMesh& scan,
                                 const BodyFrame& frame, const FlatPatternOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  FlatPatternResult r;
  r.panels.resize(panels.panels.size());
  for (size_t p = 0; p < panels.panels.size(); ++p) {
    const auto tp = std::chrono::steady_clock::now();
    FlatPanel& fp = r.panels[p];
    fp.panel = static_cast<int>(p);
    try {
      flattenAndOutline(panels.panels[p], frame, options, fp);
    } catch (const Error& e) {
      fp.error = e.what();
      r.warnings.push_back(fmt::format("panel '{}' of {} not flattened: {}", panels.panels[p].name,
                                       panels.panels[p].garment, e.what()));
    }
    fp.seconds = secondsSince(tp);
  }
  // Sample counts: a stitched pair shares the count of its mean 2D length, so that a simulator
  // can pair the two edges vertex to vertex.
  std::vector<std::vector<int>> counts(panels.panels.size());
  const double target = options.remesh.targetEdgeLength;
  for (size_t p = 0; p < panels.panels.size(); ++p) {
    const FlatPanel& fp = r.panels[p];
    if (!fp.error.empty()) continue;
    counts[p].resize(fp.edges.size());
    for (size_t e = 0; e < fp.edges.size(); ++e)
      counts[p][e] = boundarySampleCount(fp.edges[e].length2d, target);
  }
  for (size_t p = 0; p < panels.panels.size(); ++p) {
    const Panel& panel = panels.panels[p];
    for (size_t e = 0; e < panel.edges.size(); ++e) {
      const PanelEdge& edge = panel.edges[e];
      if (edge.opening || edge.partnerPanel < 0 || edge.partnerEdge < 0) continue;
      const std::pair<int, int> a{static_cast<int>(p), static_cast<int>(e)};
      const std::pair<int, int> b{edge.partnerPanel, edge.partnerEdge};
      if (!(a < b)) continue;
      SeamPair s{a.first, a.second, b.first, b.second};
      const FlatPanel& fa = r.panels[a.first];
      const FlatPanel& fb = r.panels[b.first];
      if (fa.error.empty()) s.lengthA = fa.edges[a.second].length2d;
      if (fb.error.empty()) s.lengthB = fb.edges[b.second].length2d;
      const double mean = fa.error.empty() && fb.error.empty() ? 0.5 * (s.lengthA + s.lengthB)
                                                               : std::max(s.lengthA, s.lengthB);
      s.samples = boundarySampleCount(mean, target);
      if (fa.error.empty()) counts[a.first][a.second] = s.samples;
      if (fb.error.empty()) counts[b.first][b.second] = s.samples;
      r.seams.push_back(s);
    }
  }
  for (size_t p = 0; p < panels.panels.size(); ++p) {
    FlatPanel& fp = r.panels[p];
    if (!fp.error.empty()) continue;
    const auto tp = std::chrono::steady_clock::now();
    try {
      remesh(panels.panels[p], scan, counts[p], options, fp);
    } catch (const Error& e) {
      fp.error = e.what();
      r.warnings.push_back(fmt::format("panel '{}' of {} not remeshed: {}", panels.panels[p].name,
                                       panels.panels[p].garment, e.what()));
    }
    fp.seconds += secondsSince(tp);
  }
  r.seconds = secondsSince(t0);
  return r;
}

}  // namespace s2p
