#include "pattern/flatten_metrics.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "pattern/grain_frame.h"

namespace s2p {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;
using Segment2 = Kernel::Segment_2;

// Area-weighted median, 95th percentile and max of values (weights ≥ 0).
StrainSummary weightedSummary(const std::vector<double>& values, const Eigen::VectorXd& weight) {
  StrainSummary s;
  if (values.empty()) return s;
  std::vector<int> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values[a] < values[b]; });
  const double total = weight.sum();
  auto quantile = [&](double q) {
    double acc = 0.0;
    for (int i : order) {
      acc += weight(i);
      if (acc >= q * total) return values[i];
    }
    return values[order.back()];
  };
  s.median = quantile(0.5);
  s.p95 = quantile(0.95);
  s.max = values[order.back()];
  return s;
}

}  // namespace

bool polygonSelfIntersects(const Eigen::MatrixX2d& uv, const std::vector<int>& loop,
                           std::vector<std::pair<int, int>>* crossings) {
  const int n = static_cast<int>(loop.size());
  if (n < 3) return true;
  auto point = [&](int i) { return Point2(uv(loop[i % n], 0), uv(loop[i % n], 1)); };
  // Records an offending pair; true when the search may stop (no list asked for).
  auto found = [&](int i, int j) {
    if (!crossings) return true;
    crossings->emplace_back(std::min(i, j) % n, std::max(i, j) % n);
    return false;
  };
  // Adjacent edges fold back when collinear and pointing back over each other.
  for (int i = 0; i < n; ++i) {
    const Point2 a = point(i), b = point(i + 1), c = point(i + 2);
    if (a == b && found(i, i + 1)) return true;
    if (a != b && CGAL::orientation(a, b, c) == CGAL::COLLINEAR &&
        (a.x() - b.x()) * (c.x() - b.x()) + (a.y() - b.y()) * (c.y() - b.y()) > 0.0 &&
        found(i, i + 1))
      return true;
  }
  const auto done = [&] {
    if (!crossings) return false;
    std::sort(crossings->begin(), crossings->end());
    crossings->erase(std::unique(crossings->begin(), crossings->end()), crossings->end());
    return !crossings->empty();
  };
  if (n == 3) return done();
  // Uniform grid; each edge goes into every cell its bounding box overlaps.
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  double meanLength = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d p = uv.row(loop[i]).transpose();
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    meanLength += (uv.row(loop[(i + 1) % n]) - uv.row(loop[i])).norm() / n;
  }
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  // At least the mean edge length, and at most ~4n cells in all.
  const double cell = std::max(
      {meanLength, extent / 4096.0, std::sqrt((hi.x() - lo.x()) * (hi.y() - lo.y()) / (4.0 * n))});
  const int nx = std::max(1, static_cast<int>((hi.x() - lo.x()) / cell) + 1);
  const int ny = std::max(1, static_cast<int>((hi.y() - lo.y()) / cell) + 1);
  auto cellX = [&](double x) {
    return std::clamp(static_cast<int>((x - lo.x()) / cell), 0, nx - 1);
  };
  auto cellY = [&](double y) {
    return std::clamp(static_cast<int>((y - lo.y()) / cell), 0, ny - 1);
  };
  std::vector<std::vector<int>> cells(static_cast<size_t>(nx) * ny);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d a = uv.row(loop[i]).transpose(),
                          b = uv.row(loop[(i + 1) % n]).transpose();
    for (int y = cellY(std::min(a.y(), b.y())); y <= cellY(std::max(a.y(), b.y())); ++y)
      for (int x = cellX(std::min(a.x(), b.x())); x <= cellX(std::max(a.x(), b.x())); ++x)
        cells[static_cast<size_t>(y) * nx + x].push_back(i);
  }
  for (const std::vector<int>& bucket : cells)
    for (size_t s = 0; s < bucket.size(); ++s)
      for (size_t t = s + 1; t < bucket.size(); ++t) {
        const int i = bucket[s], j = bucket[t];
        const int gap = std::abs(i - j);
        if (gap == 1 || gap == n - 1) continue;  // adjacent: share a corner, checked above
        if (CGAL::do_intersect(Segment2(point(i), point(i + 1)),
                               Segment2(point(j), point(j + 1))) &&
            found(i, j))
          return true;
      }
  return done();
}

FlatteningMetrics flatteningMetrics(const TriMesh& panel3d, const Eigen::MatrixX2d& uv,
                                    const Eigen::Vector3d& grain) {
  const int nV = panel3d.numVertices(), nF = panel3d.numFaces();
  if (uv.rows() != nV || !uv.allFinite())
    throw InputError(fmt::format("flatteningMetrics: uv has {} rows{}, the panel {} vertices",
                                 uv.rows(), uv.allFinite() ? "" : " with non-finite values", nV));
  FlatteningMetrics m;
  const GrainFrames frames = grainFrames(panel3d, grain);
  const Eigen::MatrixX4d J = grainJacobians(frames, panel3d.F, uv);
  std::vector<double> warp(nF), weft(nF);
  double distortionSum = 0.0;
  for (int f = 0; f < nF; ++f) {
    const Eigen::Vector2d a = uv.row(panel3d.F(f, 0)).transpose();
    const Eigen::Vector2d b = uv.row(panel3d.F(f, 1)).transpose() - a;
    const Eigen::Vector2d c = uv.row(panel3d.F(f, 2)).transpose() - a;
    const double area2d = 0.5 * (b.x() * c.y() - b.y() * c.x());
    const double area3d = frames.area(f);
    m.area2d += area2d;
    m.area3d += area3d;
    if (!(area2d > 0.0)) ++m.invertedFaces;
    const double distortion = area2d > 0.0 && area3d > 0.0
                                  ? std::abs(std::log(area2d / area3d))
                                  : std::numeric_limits<double>::infinity();
    if (std::isfinite(distortion)) distortionSum += area3d * distortion;
    m.areaDistortionMax = std::max(m.areaDistortionMax, distortion);
    warp[f] = std::abs(std::hypot(J(f, 0), J(f, 1)) - 1.0);
    weft[f] = std::abs(std::hypot(J(f, 2), J(f, 3)) - 1.0);
  }
  if (m.area3d > 0.0) m.areaDistortionMean = distortionSum / m.area3d;
  m.warp = weightedSummary(warp, frames.area);
  m.weft = weightedSummary(weft, frames.area);

  const MeshTopology topology(panel3d.F, nV);
  const Eigen::MatrixX2i& edges = topology.edges();
  for (int e = 0; e < edges.rows(); ++e) {
    const double l3 = (panel3d.V.row(edges(e, 0)) - panel3d.V.row(edges(e, 1))).norm();
    const double l2 = (uv.row(edges(e, 0)) - uv.row(edges(e, 1))).norm();
    if (l3 > 0.0) m.edgeLengthErrorMax = std::max(m.edgeLengthErrorMax, std::abs(l2 / l3 - 1.0));
  }
  for (const std::vector<int>& loop : topology.boundaryLoops()) {
    const int n = static_cast<int>(loop.size());
    for (int i = 0; i < n; ++i) {
      m.boundaryLength3d += (panel3d.V.row(loop[(i + 1) % n]) - panel3d.V.row(loop[i])).norm();
      m.boundaryLength2d += (uv.row(loop[(i + 1) % n]) - uv.row(loop[i])).norm();
    }
    m.boundarySelfIntersects = m.boundarySelfIntersects || polygonSelfIntersects(uv, loop);
  }
  if (m.boundaryLength3d > 0.0)
    m.boundaryLengthError = std::abs(m.boundaryLength2d - m.boundaryLength3d) / m.boundaryLength3d;
  return m;
}

}  // namespace s2p
