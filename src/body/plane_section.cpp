#include "body/plane_section.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace s2p {
namespace {

Eigen::Vector3d checkedUnitNormal(const Eigen::Vector3d& normal, const char* what) {
  const double len = normal.norm();
  if (!normal.allFinite() || !(len > 0))
    throw InputError(
        fmt::format("{}: the plane normal ({}, {}, {}) is zero or not finite; "
                    "give a non-zero direction",
                    what, normal.x(), normal.y(), normal.z()));
  return normal / len;
}

// Orthonormal (u, v) with u × v = n̂: 2D coordinates in the plane ⟂ n.
std::pair<Eigen::Vector3d, Eigen::Vector3d> planeBasis(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = n.cross(a).normalized();
  return {u, n.cross(u)};
}

Eigen::MatrixX2d project(const Eigen::MatrixX3d& P, const Eigen::Vector3d& normal) {
  const auto [u, v] = planeBasis(normal.normalized());
  Eigen::MatrixX2d Q(P.rows(), 2);
  Q.col(0) = P * u;
  Q.col(1) = P * v;
  return Q;
}

double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

}  // namespace

MeshSlicer::MeshSlicer(const TriMesh& mesh) : mesh_(mesh) {
  validateMesh(mesh, "plane section");
  const int nf = mesh.numFaces();
  // (min, max, half-edge) sorted so equal undirected edges are adjacent.
  std::vector<std::array<int, 3>> half(3 * static_cast<size_t>(nf));
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      half[3 * f + k] = {std::min(a, b), std::max(a, b), 3 * f + k};
    }
  std::sort(half.begin(), half.end());
  faceEdge_.resize(nf, 3);
  std::vector<std::array<int, 2>> edges;
  for (size_t i = 0; i < half.size(); ++i) {
    if (i == 0 || half[i][0] != half[i - 1][0] || half[i][1] != half[i - 1][1])
      edges.push_back({half[i][0], half[i][1]});
    faceEdge_(half[i][2] / 3, half[i][2] % 3) = static_cast<int>(edges.size()) - 1;
  }
  edges_.resize(static_cast<Eigen::Index>(edges.size()), 2);
  for (size_t e = 0; e < edges.size(); ++e) edges_.row(e) << edges[e][0], edges[e][1];

  // Height bins (~8 faces each): a face is listed in every bin its height range overlaps.
  yMin_ = mesh.V.col(1).minCoeff();
  yMax_ = mesh.V.col(1).maxCoeff();
  if (!(yMax_ > yMin_)) return;  // flat in y: horizontal planes scan every face
  const int nb = std::clamp(nf / 8, 1, 4096);
  binHeight_ = (yMax_ - yMin_) / nb;
  auto binOf = [&](double y) {
    return std::clamp(static_cast<int>((y - yMin_) / binHeight_), 0, nb - 1);
  };
  std::vector<std::array<int, 2>> range(nf);
  binStart_.assign(nb + 1, 0);
  for (int f = 0; f < nf; ++f) {
    double lo = mesh.V(mesh.F(f, 0), 1), hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = std::min(lo, mesh.V(mesh.F(f, k), 1));
      hi = std::max(hi, mesh.V(mesh.F(f, k), 1));
    }
    range[f] = {binOf(lo), binOf(hi)};
    for (int b = range[f][0]; b <= range[f][1]; ++b) ++binStart_[b + 1];
  }
  for (int b = 0; b < nb; ++b) binStart_[b + 1] += binStart_[b];
  binFaces_.resize(binStart_[nb]);
  std::vector<int> fill(binStart_.begin(), binStart_.end() - 1);
  for (int f = 0; f < nf; ++f)
    for (int b = range[f][0]; b <= range[f][1]; ++b) binFaces_[fill[b]++] = f;
}

std::vector<SectionLoop> MeshSlicer::section(const Eigen::Vector3d& point,
                                             const Eigen::Vector3d& normal) const {
  const Eigen::Vector3d n = checkedUnitNormal(normal, "plane section");
  if (!point.allFinite())
    throw InputError("plane section: the plane's point is not finite; give finite coordinates");
  auto dist = [&](int v) { return n.dot(mesh_.V.row(v).transpose() - point); };

  // Faces the plane can cross: for a horizontal plane those of its height bin, else all.
  const bool horizontal = n.x() == 0 && n.z() == 0 && !binStart_.empty();
  int first = 0, last = mesh_.numFaces();
  if (horizontal) {
    const double y = point.y();
    if (y < yMin_ || y > yMax_) return {};
    const int bin = std::min(numBins() - 1, static_cast<int>((y - yMin_) / binHeight_));
    first = binStart_[bin];
    last = binStart_[bin + 1];
  }

  // Segments: one per crossed face, between the crossing points of two of its edges.
  std::vector<std::array<int, 2>> segEdges;
  for (int i = first; i < last; ++i) {
    const int f = horizontal ? binFaces_[i] : i;
    const bool s[3] = {dist(mesh_.F(f, 0)) >= 0, dist(mesh_.F(f, 1)) >= 0,
                       dist(mesh_.F(f, 2)) >= 0};
    if (s[0] == s[1] && s[1] == s[2]) continue;
    std::array<int, 2> seg{};
    int m = 0;
    for (int k = 0; k < 3; ++k)
      if (s[k] != s[(k + 1) % 3]) seg[m++] = faceEdge_(f, k);
    segEdges.push_back(seg);
  }
  // Nodes: the crossed edges, sorted; a crossing point per node.
  std::vector<int> nodeEdge;
  nodeEdge.reserve(2 * segEdges.size());
  for (const auto& se : segEdges) nodeEdge.insert(nodeEdge.end(), se.begin(), se.end());
  std::sort(nodeEdge.begin(), nodeEdge.end());
  nodeEdge.erase(std::unique(nodeEdge.begin(), nodeEdge.end()), nodeEdge.end());
  std::vector<Eigen::Vector3d> nodePos(nodeEdge.size());
  for (size_t i = 0; i < nodeEdge.size(); ++i) {
    const int a = edges_(nodeEdge[i], 0), b = edges_(nodeEdge[i], 1);
    const double da = dist(a), db = dist(b);
    // A vertex on the plane is its own crossing point, exactly (no 1-ulp duplicates).
    nodePos[i] =
        db == 0   ? Eigen::Vector3d(mesh_.V.row(b))
        : da == 0 ? Eigen::Vector3d(mesh_.V.row(a))
                  : Eigen::Vector3d(mesh_.V.row(a).transpose() +
                                    da / (da - db) * (mesh_.V.row(b) - mesh_.V.row(a)).transpose());
  }
  auto nodeOf = [&](int e) {
    return static_cast<int>(std::lower_bound(nodeEdge.begin(), nodeEdge.end(), e) -
                            nodeEdge.begin());
  };
  std::vector<std::array<int, 2>> segs(segEdges.size());
  for (size_t i = 0; i < segEdges.size(); ++i)
    segs[i] = {nodeOf(segEdges[i][0]), nodeOf(segEdges[i][1])};

  // Node → incident segments (CSR).
  const int nn = static_cast<int>(nodePos.size());
  std::vector<int> start(nn + 1, 0), inc(2 * segs.size());
  for (const auto& s : segs) ++start[s[0] + 1], ++start[s[1] + 1];
  for (int i = 0; i < nn; ++i) start[i + 1] += start[i];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (size_t i = 0; i < segs.size(); ++i)
    for (int k : segs[i]) inc[fill[k]++] = static_cast<int>(i);

  std::vector<char> used(segs.size(), 0);
  auto nextSeg = [&](int node) {
    for (int i = start[node]; i < start[node + 1]; ++i)
      if (!used[inc[i]]) return inc[i];
    return -1;
  };
  std::vector<SectionLoop> loops;
  auto walk = [&](int first) {
    std::vector<int> chain{first};
    int cur = first;
    for (int s = nextSeg(cur); s >= 0; s = nextSeg(cur)) {
      used[s] = 1;
      cur = segs[s][0] == cur ? segs[s][1] : segs[s][0];
      chain.push_back(cur);
    }
    const bool closed = chain.size() > 2 && chain.back() == first;
    if (closed) chain.pop_back();
    // Drop repeated points (the plane through a vertex makes its edges cross at one spot).
    std::vector<Eigen::Vector3d> pts;
    for (int node : chain)
      if (pts.empty() || (nodePos[node] - pts.back()).norm() > 0) pts.push_back(nodePos[node]);
    while (closed && pts.size() > 1 && (pts.back() - pts.front()).norm() == 0) pts.pop_back();
    if (pts.size() < 2) return;
    SectionLoop loop;
    loop.closed = closed && pts.size() > 2;
    loop.points.resize(static_cast<Eigen::Index>(pts.size()), 3);
    for (size_t i = 0; i < pts.size(); ++i) loop.points.row(i) = pts[i].transpose();
    loops.push_back(std::move(loop));
  };
  for (int node = 0; node < nn; ++node)  // open pieces start at a node of odd degree
    if ((start[node + 1] - start[node]) % 2 == 1 && nextSeg(node) >= 0) walk(node);
  for (size_t s = 0; s < segs.size(); ++s)
    if (!used[s]) walk(segs[s][0]);
  return loops;
}

std::vector<SectionLoop> planeSection(const TriMesh& mesh, const Eigen::Vector3d& point,
                                      const Eigen::Vector3d& normal) {
  return MeshSlicer(mesh).section(point, normal);
}

double convexHullPerimeter(const SectionLoop& loop, const Eigen::Vector3d& normal) {
  checkedUnitNormal(normal, "convex hull perimeter");
  if (loop.points.rows() < 2) return 0.0;
  const Eigen::MatrixX2d Q = project(loop.points, normal);
  std::vector<Eigen::Vector2d> p(Q.rows());
  for (Eigen::Index i = 0; i < Q.rows(); ++i) p[i] = Q.row(i).transpose();
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  // Andrew's monotone chain: lower then upper hull, counter-clockwise.
  std::vector<Eigen::Vector2d> hull(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  double perimeter = 0;
  for (size_t i = 0; i + 1 < k; ++i) perimeter += (hull[i + 1] - hull[i]).norm();
  return perimeter;  // hull[k-1] == hull[0], so the closing edge is counted
}

double polylineLength(const SectionLoop& loop) {
  const Eigen::Index n = loop.points.rows();
  if (n < 2) return 0.0;
  double len = 0;
  for (Eigen::Index i = 0; i + 1 < n; ++i)
    len += (loop.points.row(i + 1) - loop.points.row(i)).norm();
  if (loop.closed) len += (loop.points.row(0) - loop.points.row(n - 1)).norm();
  return len;
}

double enclosedArea(const SectionLoop& loop, const Eigen::Vector3d& normal) {
  checkedUnitNormal(normal, "enclosed area");
  if (!loop.closed || loop.points.rows() < 3) return 0.0;
  const Eigen::MatrixX2d Q = project(loop.points, normal);
  double twice = 0;
  for (Eigen::Index i = 0, n = Q.rows(); i < n; ++i) {
    const Eigen::Index j = (i + 1) % n;
    twice += Q(i, 0) * Q(j, 1) - Q(j, 0) * Q(i, 1);
  }
  return 0.5 * std::abs(twice);
}

bool loopEncloses(const SectionLoop& loop, const Eigen::Vector3d& point,
                  const Eigen::Vector3d& normal) {
  checkedUnitNormal(normal, "loop encloses");
  if (!loop.closed || loop.points.rows() < 3) return false;
  const Eigen::MatrixX2d Q = project(loop.points, normal);
  const auto [u, v] = planeBasis(normal.normalized());
  const double px = point.dot(u), py = point.dot(v);
  bool inside = false;
  for (Eigen::Index i = 0, n = Q.rows(), j = n - 1; i < n; j = i++) {
    const double yi = Q(i, 1), yj = Q(j, 1);
    if ((yi > py) != (yj > py) && px < Q(j, 0) + (py - yj) / (yi - yj) * (Q(i, 0) - Q(j, 0)))
      inside = !inside;
  }
  return inside;
}

double distanceToLoop(const SectionLoop& loop, const Eigen::Vector3d& point) {
  const Eigen::Index n = loop.points.rows();
  if (n == 0) return std::numeric_limits<double>::infinity();
  double best = (loop.points.row(0).transpose() - point).norm();
  const Eigen::Index segments = loop.closed ? n : n - 1;
  for (Eigen::Index i = 0; i < segments; ++i) {
    const Eigen::Vector3d a = loop.points.row(i), b = loop.points.row((i + 1) % n);
    const Eigen::Vector3d ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((point - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * ab - point).norm());
  }
  return best;
}

}  // namespace s2p
