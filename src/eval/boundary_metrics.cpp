#include "eval/boundary_metrics.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "core/error.h"
#include "core/mesh_topology.h"

namespace s2p {
namespace {

// Polyline vertices as a list including the closing vertex when closed (and > 2 points).
std::vector<Eigen::Vector3d> vertexList(const Eigen::MatrixX3d& c, bool closed) {
  std::vector<Eigen::Vector3d> p;
  for (Eigen::Index i = 0; i < c.rows(); ++i) p.push_back(c.row(i).transpose());
  if (closed && c.rows() > 2) p.push_back(c.row(0).transpose());
  return p;
}

bool isClosed(const TrueBoundary& b, std::size_t c) {
  return c < b.closed.size() && b.closed[c];
}

double pointSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                            const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

bool hasPoints(const TrueBoundary* b) {
  if (!b) return false;
  for (const auto& c : b->curves)
    if (c.rows() > 0) return true;
  return false;
}

}  // namespace

std::vector<TrueBoundary> extractLabelBoundaries(const LabelledMesh& m, bool skipGap) {
  validateLabelledMesh(m, "the labelled mesh");
  const MeshTopology topo(m.mesh.F, m.mesh.numVertices());
  // Label pair → its edges (vertex pairs).
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> pairEdges;
  const int gap = static_cast<int>(Label::Gap);
  for (int e = 0; e < topo.numEdges(); ++e) {
    if (topo.edgeFaceCount(e) != 2) continue;
    const std::vector<int> f = topo.edgeFaces(e);
    int la = m.faceLabel(f[0]), lb = m.faceLabel(f[1]);
    if (la == lb) continue;
    if (skipGap && (la == gap || lb == gap)) {
      // A garment meeting gap-filling triangles ends there: its rim under a hanging hem is the
      // garment's boundary with the skin, as in truth.json (paper §5.2). Other gap edges belong
      // to no boundary.
      const int other = la == gap ? lb : la;
      if (other != static_cast<int>(Label::Upper) && other != static_cast<int>(Label::Lower))
        continue;
      la = static_cast<int>(Label::Skin), lb = other;
    }
    if (lb < la) std::swap(la, lb);
    pairEdges[{la, lb}].emplace_back(topo.edges()(e, 0), topo.edges()(e, 1));
  }

  std::vector<TrueBoundary> out;
  for (const auto& [labels, edges] : pairEdges) {
    TrueBoundary tb;
    tb.a = static_cast<Label>(labels.first);
    tb.b = static_cast<Label>(labels.second);
    std::map<int, std::vector<int>> incident;  // vertex → indices into edges
    for (std::size_t i = 0; i < edges.size(); ++i) {
      incident[edges[i].first].push_back(static_cast<int>(i));
      incident[edges[i].second].push_back(static_cast<int>(i));
    }
    std::vector<bool> used(edges.size(), false);
    auto other = [&](int e, int v) {
      return edges[e].first == v ? edges[e].second : edges[e].first;
    };
    auto walk = [&](int start, int firstEdge) {
      std::vector<int> chain{start};
      int v = start, e = firstEdge;
      while (true) {
        used[static_cast<std::size_t>(e)] = true;
        v = other(e, v);
        chain.push_back(v);
        const auto& inc = incident[v];
        if (inc.size() != 2) break;  // a branch or an end
        const int next = inc[0] == e ? inc[1] : inc[0];
        if (used[static_cast<std::size_t>(next)]) break;  // back at the start of a loop
        e = next;
      }
      return chain;
    };
    auto emit = [&](std::vector<int> chain, bool closed) {
      if (closed) chain.pop_back();  // last vertex repeats the first
      Eigen::MatrixX3d c(static_cast<Eigen::Index>(chain.size()), 3);
      for (std::size_t i = 0; i < chain.size(); ++i)
        c.row(static_cast<Eigen::Index>(i)) = m.mesh.V.row(chain[i]);
      tb.curves.push_back(std::move(c));
      tb.closed.push_back(closed);
    };
    // Open chains start at ends and branches; what is left are closed loops.
    for (const auto& [v, inc] : incident)
      if (inc.size() != 2)
        for (int e : inc)
          if (!used[static_cast<std::size_t>(e)]) emit(walk(v, e), false);
    for (std::size_t e = 0; e < edges.size(); ++e)
      if (!used[e]) {
        std::vector<int> chain = walk(edges[e].first, static_cast<int>(e));
        const bool closed = chain.size() > 3 && chain.front() == chain.back();
        emit(std::move(chain), closed);
      }
    out.push_back(std::move(tb));
  }
  return out;
}

Eigen::MatrixX3d samplePolyline(const Eigen::MatrixX3d& curve, bool closed, double maxSpacing) {
  if (!(maxSpacing > 0))
    throw InputError(fmt::format("sample spacing {} m is not positive", maxSpacing));
  if (curve.rows() == 0) return Eigen::MatrixX3d(0, 3);
  const std::vector<Eigen::Vector3d> p = vertexList(curve, closed);
  std::vector<double> cum{0.0};
  for (std::size_t i = 1; i < p.size(); ++i) cum.push_back(cum.back() + (p[i] - p[i - 1]).norm());
  const double length = cum.back();
  if (!std::isfinite(length)) throw InputError("a boundary curve has non-finite coordinates");
  if (length == 0) return curve.topRows(1);
  const auto n = static_cast<Eigen::Index>(std::ceil(length / maxSpacing));
  const bool loop = closed && curve.rows() > 2;
  const Eigen::Index count = loop ? n : n + 1;
  Eigen::MatrixX3d out(count, 3);
  std::size_t seg = 1;
  for (Eigen::Index i = 0; i < count; ++i) {
    const double s = length * static_cast<double>(i) / static_cast<double>(n);
    while (seg + 1 < p.size() && cum[seg] < s) ++seg;
    const double len = cum[seg] - cum[seg - 1];
    const double t = len > 0 ? std::clamp((s - cum[seg - 1]) / len, 0.0, 1.0) : 0.0;
    out.row(i) = ((1 - t) * p[seg - 1] + t * p[seg]).transpose();
  }
  return out;
}

Eigen::VectorXd distanceToCurves(const Eigen::MatrixX3d& P, const TrueBoundary& curves) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segs;
  for (std::size_t c = 0; c < curves.curves.size(); ++c) {
    const std::vector<Eigen::Vector3d> p = vertexList(curves.curves[c], isClosed(curves, c));
    if (p.size() == 1) segs.emplace_back(p[0], p[0]);
    for (std::size_t i = 1; i < p.size(); ++i) segs.emplace_back(p[i - 1], p[i]);
  }
  Eigen::VectorXd d = Eigen::VectorXd::Constant(P.rows(), std::numeric_limits<double>::infinity());
  tbb::parallel_for(Eigen::Index{0}, P.rows(), [&](Eigen::Index i) {
    const Eigen::Vector3d q = P.row(i).transpose();
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : segs) best = std::min(best, pointSegmentDistance(q, a, b));
    d(i) = best;
  });
  return d;
}

DistanceStats distanceStats(const Eigen::VectorXd& d) {
  DistanceStats s;
  s.count = static_cast<int>(d.size());
  if (d.size() == 0) return s;
  std::vector<double> v(d.data(), d.data() + d.size());
  std::sort(v.begin(), v.end());
  s.mean = d.mean();
  s.max = v.back();
  const double r = 0.95 * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(r));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  s.p95 = v[lo] + (r - static_cast<double>(lo)) * (v[hi] - v[lo]);
  return s;
}

BoundaryScore compareBoundary(const TrueBoundary& truth, const TrueBoundary* pred,
                              const BoundaryMetricOptions& opt) {
  BoundaryScore s;
  s.a = truth.a;
  s.b = truth.b;
  s.trueLength = truth.length();
  if (!hasPoints(pred) || !hasPoints(&truth)) return s;
  s.missing = false;
  s.predLength = pred->length();
  s.roughness =
      s.trueLength > 0 ? s.predLength / s.trueLength : std::numeric_limits<double>::infinity();
  auto samples = [&](const TrueBoundary& b) {
    std::vector<Eigen::MatrixX3d> parts;
    Eigen::Index n = 0;
    for (std::size_t c = 0; c < b.curves.size(); ++c) {
      parts.push_back(samplePolyline(b.curves[c], isClosed(b, c), opt.sampleSpacing));
      n += parts.back().rows();
    }
    Eigen::MatrixX3d all(n, 3);
    Eigen::Index row = 0;
    for (const auto& p : parts) {
      all.middleRows(row, p.rows()) = p;
      row += p.rows();
    }
    return all;
  };
  const Eigen::VectorXd dp = distanceToCurves(samples(*pred), truth);
  const Eigen::VectorXd dt = distanceToCurves(samples(truth), *pred);
  Eigen::VectorXd both(dp.size() + dt.size());
  both << dp, dt;
  s.predToTrue = distanceStats(dp);
  s.trueToPred = distanceStats(dt);
  s.pooled = distanceStats(both);
  return s;
}

}  // namespace s2p
