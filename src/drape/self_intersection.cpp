// Triangle–triangle intersections between faces that share no (sewn) vertex: a uniform grid of
// face boxes, then segment–triangle tests both ways.
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "drape/drape.h"

namespace s2p {
namespace {

using Eigen::Vector3d;

// Whether segment pq crosses triangle abc (Möller–Trumbore; touching within 1e-12 counts).
bool segmentHitsTriangle(const Vector3d& p, const Vector3d& q, const Vector3d& a, const Vector3d& b,
                         const Vector3d& c) {
  const Vector3d d = q - p, e1 = b - a, e2 = c - a;
  const Vector3d h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-18) return false;  // parallel (coplanar overlaps are not counted)
  const double inv = 1.0 / det;
  const Vector3d s = p - a;
  const double u = s.dot(h) * inv;
  if (u < 0 || u > 1) return false;
  const Vector3d qq = s.cross(e1);
  const double v = d.dot(qq) * inv;
  if (v < 0 || u + v > 1) return false;
  const double t = e2.dot(qq) * inv;
  return t >= 0 && t <= 1;
}

bool trianglesIntersect(const Vector3d* t, const Vector3d* u) {
  for (int k = 0; k < 3; ++k) {
    if (segmentHitsTriangle(t[k], t[(k + 1) % 3], u[0], u[1], u[2])) return true;
    if (segmentHitsTriangle(u[k], u[(k + 1) % 3], t[0], t[1], t[2])) return true;
  }
  return false;
}

}  // namespace

int countSelfIntersections(const TriMesh& mesh, const std::vector<int>& weld) {
  const int nf = mesh.numFaces();
  if (nf < 2) return 0;
  auto rep = [&](int v) { return weld.empty() ? v : weld[v]; };
  std::vector<Eigen::AlignedBox3d> box(nf);
  double edge = 0;
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) box[f].extend(Vector3d(mesh.V.row(mesh.F(f, k))));
    edge += box[f].diagonal().norm();
  }
  const double cell = std::max(2 * edge / nf, 1e-9);
  auto key = [](int64_t i, int64_t j, int64_t k) {
    return (i & 0x1FFFFF) | ((j & 0x1FFFFF) << 21) | ((k & 0x1FFFFF) << 42);
  };
  auto cellOf = [&](const Vector3d& p) {
    return Eigen::Array<int64_t, 3, 1>((p.array() / cell).floor().cast<int64_t>());
  };
  std::unordered_map<int64_t, std::vector<int>> grid;
  for (int f = 0; f < nf; ++f) {
    const auto lo = cellOf(box[f].min()), hi = cellOf(box[f].max());
    for (int64_t i = lo[0]; i <= hi[0]; ++i)
      for (int64_t j = lo[1]; j <= hi[1]; ++j)
        for (int64_t k = lo[2]; k <= hi[2]; ++k) grid[key(i, j, k)].push_back(f);
  }
  std::vector<int> count(nf, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, nf, 256), [&](const tbb::blocked_range<int>& r) {
    std::vector<int> cand;
    for (int f = r.begin(); f < r.end(); ++f) {
      cand.clear();
      const auto lo = cellOf(box[f].min()), hi = cellOf(box[f].max());
      for (int64_t i = lo[0]; i <= hi[0]; ++i)
        for (int64_t j = lo[1]; j <= hi[1]; ++j)
          for (int64_t k = lo[2]; k <= hi[2]; ++k) {
            const auto it = grid.find(key(i, j, k));
            if (it == grid.end()) continue;
            for (int g : it->second)
              if (g > f) cand.push_back(g);
          }
      std::sort(cand.begin(), cand.end());
      cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
      const int a[3] = {rep(mesh.F(f, 0)), rep(mesh.F(f, 1)), rep(mesh.F(f, 2))};
      Vector3d t[3];
      for (int k = 0; k < 3; ++k) t[k] = mesh.V.row(mesh.F(f, k));
      for (int g : cand) {
        if (!box[f].intersects(box[g])) continue;
        bool shared = false;
        for (int k = 0; k < 3 && !shared; ++k) {
          const int b = rep(mesh.F(g, k));
          shared = b == a[0] || b == a[1] || b == a[2];
        }
        if (shared) continue;
        Vector3d u[3];
        for (int k = 0; k < 3; ++k) u[k] = mesh.V.row(mesh.F(g, k));
        if (trianglesIntersect(t, u)) ++count[f];
      }
    }
  });
  return std::accumulate(count.begin(), count.end(), 0);
}

}  // namespace s2p
