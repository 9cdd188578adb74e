#include "io/cleanup.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fmt/format.h>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

#include "core/error.h"
#include "core/mesh_topology.h"

namespace s2p {

namespace {

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey&) const = default;
};

struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

struct TriKey {
  std::array<int, 3> v;
  bool operator==(const TriKey&) const = default;
};

struct TriHash {
  std::size_t operator()(const TriKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.v[0]) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(k.v[1]) * 0xC2B2AE3D27D4EB4Full + (h >> 7);
    h ^= static_cast<std::uint64_t>(k.v[2]) * 0x165667B19E3779F9ull + (h >> 11);
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
};

// Greedy clustering in vertex order: each vertex joins the first earlier representative within
// `tol` found in its 27 neighbouring grid cells (cell size = tol), else becomes one. Returns
// #V representative ids in [0, #reps) and the representatives' original indices.
std::vector<int> weldMap(const Eigen::MatrixX3d& V, double tol, std::vector<int>& repOf) {
  const int nv = static_cast<int>(V.rows());
  std::vector<int> map(nv);
  repOf.clear();
  if (tol <= 0) {
    std::unordered_map<CellKey, int, CellHash> exact;
    exact.reserve(static_cast<std::size_t>(nv));
    for (int v = 0; v < nv; ++v) {
      CellKey k{};
      const double x = V(v, 0) + 0.0, y = V(v, 1) + 0.0, z = V(v, 2) + 0.0;  // −0 → +0
      std::memcpy(&k.x, &x, 8);
      std::memcpy(&k.y, &y, 8);
      std::memcpy(&k.z, &z, 8);
      auto [it, inserted] = exact.try_emplace(k, static_cast<int>(repOf.size()));
      if (inserted) repOf.push_back(v);
      map[v] = it->second;
    }
    return map;
  }
  const Eigen::RowVector3d lo = V.colwise().minCoeff();
  std::unordered_map<CellKey, int, CellHash> head;  // cell → first representative in it
  head.reserve(static_cast<std::size_t>(nv));
  std::vector<int> next;  // representative → next representative in the same cell
  const double tol2 = tol * tol;
  for (int v = 0; v < nv; ++v) {
    const Eigen::RowVector3d p = V.row(v);
    const Eigen::RowVector3d q = (p - lo) / tol;
    const CellKey c{static_cast<std::int64_t>(std::floor(q[0])),
                    static_cast<std::int64_t>(std::floor(q[1])),
                    static_cast<std::int64_t>(std::floor(q[2]))};
    int found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          auto it = head.find({c.x + dx, c.y + dy, c.z + dz});
          if (it == head.end()) continue;
          for (int r = it->second; r >= 0; r = next[r])
            if ((V.row(repOf[r]) - p).squaredNorm() <= tol2) {
              found = r;
              break;
            }
        }
    if (found < 0) {
      found = static_cast<int>(repOf.size());
      repOf.push_back(v);
      auto [it, inserted] = head.try_emplace(c, found);
      next.push_back(inserted ? -1 : it->second);
      it->second = found;
    }
    map[v] = found;
  }
  return map;
}

double triangleArea(const Eigen::MatrixX3d& V, int a, int b, int c) {
  const Eigen::Vector3d p = V.row(a);
  return 0.5 * (V.row(b).transpose() - p).cross(V.row(c).transpose() - p).norm();
}

}  // namespace

CleanupReport cleanScan(Scan& scan, const CleanupOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  CleanupReport report;
  const std::string what = scan.sourcePath.empty() ? std::string("scan") : scan.sourcePath;
  TriMesh& mesh = scan.mesh;
  validateMesh(mesh, what);
  if (!(options.weldTolerance >= 0) || !std::isfinite(options.weldTolerance))
    throw InputError(fmt::format("{}: weld tolerance {} must be finite and ≥ 0", what,
                                 options.weldTolerance));
  const bool hasColour = scan.colour.rows() > 0;
  if (hasColour && scan.colour.rows() != mesh.V.rows())
    throw InputError(fmt::format("{}: {} colours for {} vertices", what, scan.colour.rows(),
                                 mesh.V.rows()));
  if (scan.texture && scan.texture->FUV.rows() != mesh.F.rows())
    throw InputError(fmt::format("{}: {} UV faces for {} faces", what, scan.texture->FUV.rows(),
                                 mesh.F.rows()));

  const BoundingBox box = boundingBox(mesh.V);
  const double diag = box.extent().norm();

  // === Weld: colours averaged with weights = incident face areas.
  std::vector<int> repOf;
  const std::vector<int> map = weldMap(mesh.V, options.weldTolerance * diag, repOf);
  const int nRep = static_cast<int>(repOf.size());
  report.weldedVertices = mesh.numVertices() - nRep;
  Eigen::MatrixX3d V(nRep, 3);
  for (int r = 0; r < nRep; ++r) V.row(r) = mesh.V.row(repOf[r]);
  Eigen::MatrixX3d colour;
  if (hasColour) {
    const Eigen::VectorXd area = faceAreas(mesh);
    Eigen::VectorXd vertexWeight = Eigen::VectorXd::Zero(mesh.numVertices());
    for (int f = 0; f < mesh.numFaces(); ++f)
      for (int k = 0; k < 3; ++k) vertexWeight(mesh.F(f, k)) += area(f);
    colour = Eigen::MatrixX3d::Zero(nRep, 3);
    Eigen::MatrixX3d plain = Eigen::MatrixX3d::Zero(nRep, 3);
    Eigen::VectorXd wsum = Eigen::VectorXd::Zero(nRep), count = Eigen::VectorXd::Zero(nRep);
    for (int v = 0; v < mesh.numVertices(); ++v) {
      colour.row(map[v]) += vertexWeight(v) * scan.colour.row(v);
      plain.row(map[v]) += scan.colour.row(v);
      wsum(map[v]) += vertexWeight(v);
      count(map[v]) += 1;
    }
    for (int r = 0; r < nRep; ++r)
      colour.row(r) = wsum(r) > 0 ? Eigen::RowVector3d(colour.row(r) / wsum(r))
                                  : Eigen::RowVector3d(plain.row(r) / count(r));
  }

  // === Degenerate and duplicate faces.
  const double areaEps = 1e-14 * diag * diag;
  std::vector<int> keep;
  keep.reserve(static_cast<std::size_t>(mesh.numFaces()));
  std::unordered_set<TriKey, TriHash> seen;
  seen.reserve(static_cast<std::size_t>(mesh.numFaces()));
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const int a = map[mesh.F(f, 0)], b = map[mesh.F(f, 1)], c = map[mesh.F(f, 2)];
    if (a == b || b == c || a == c || triangleArea(V, a, b, c) <= areaEps) {
      ++report.degenerateFaces;
      continue;
    }
    TriKey key{{a, b, c}};
    std::sort(key.v.begin(), key.v.end());
    if (!seen.insert(key).second) {
      ++report.duplicateFaces;
      continue;
    }
    keep.push_back(f);
  }
  if (keep.empty())
    throw InputError(fmt::format("{}: no face is left after removing degenerate faces; the mesh "
                                 "has no area",
                                 what));
  Eigen::MatrixX3i F(static_cast<Eigen::Index>(keep.size()), 3);
  for (std::size_t i = 0; i < keep.size(); ++i)
    for (int k = 0; k < 3; ++k) F(static_cast<Eigen::Index>(i), k) = map[mesh.F(keep[i], k)];
  if (scan.texture) {
    Eigen::MatrixX3i FUV(F.rows(), 3);
    for (std::size_t i = 0; i < keep.size(); ++i)
      FUV.row(static_cast<Eigen::Index>(i)) = scan.texture->FUV.row(keep[i]);
    scan.texture->FUV = std::move(FUV);
  }

  // === Unreferenced vertices.
  std::vector<int> newIndex(nRep, -1);
  int nv = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (newIndex[F(f, k)] < 0) newIndex[F(f, k)] = nv++;
  report.unreferencedVertices = nRep - nv;
  // Keep the original relative order of vertices (renumber by old index, not by first use).
  {
    int next = 0;
    for (int r = 0; r < nRep; ++r)
      if (newIndex[r] >= 0) newIndex[r] = next++;
  }
  Eigen::MatrixX3d V2(nv, 3);
  Eigen::MatrixX3d C2(hasColour ? nv : 0, 3);
  for (int r = 0; r < nRep; ++r)
    if (newIndex[r] >= 0) {
      V2.row(newIndex[r]) = V.row(r);
      if (hasColour) C2.row(newIndex[r]) = colour.row(r);
    }
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) F(f, k) = newIndex[F(f, k)];

  // === Non-manifold vertices: one copy per fan of faces connected through edges at v.
  {
    std::vector<int> start(nv + 1, 0);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) ++start[F(f, k) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<int> list(start.back()), fill(start.begin(), start.end() - 1);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) list[fill[F(f, k)]++] = static_cast<int>(f);
    std::vector<Eigen::RowVector3d> extraV, extraC;
    std::vector<int> parent;
    std::vector<std::pair<int, int>> neighbourFace;  // (neighbour vertex, local face)
    for (int v = 0; v < nv; ++v) {
      const int n = start[v + 1] - start[v];
      if (n < 2) continue;
      parent.resize(n);
      std::iota(parent.begin(), parent.end(), 0);
      auto find = [&](int i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
      };
      neighbourFace.clear();
      for (int i = 0; i < n; ++i) {
        const int f = list[start[v] + i];
        for (int k = 0; k < 3; ++k)
          if (F(f, k) != v) neighbourFace.emplace_back(F(f, k), i);
      }
      std::sort(neighbourFace.begin(), neighbourFace.end());
      for (std::size_t j = 1; j < neighbourFace.size(); ++j)
        if (neighbourFace[j].first == neighbourFace[j - 1].first)
          parent[find(neighbourFace[j].second)] = find(neighbourFace[j - 1].second);
      // Fan of the first face keeps v; every other fan gets a new copy.
      std::vector<int> fanVertex(n, -1);
      const int root0 = find(0);
      fanVertex[root0] = v;
      bool split = false;
      for (int i = 0; i < n; ++i) {
        const int root = find(i);
        if (fanVertex[root] < 0) {
          fanVertex[root] = nv + static_cast<int>(extraV.size());
          extraV.push_back(V2.row(v));
          if (hasColour) extraC.push_back(C2.row(v));
          split = true;
        }
        if (fanVertex[root] != v) {
          const int f = list[start[v] + i];
          for (int k = 0; k < 3; ++k)
            if (F(f, k) == v) F(f, k) = fanVertex[root];
        }
      }
      if (split) ++report.splitNonManifoldVertices;
    }
    if (!extraV.empty()) {
      const int total = nv + static_cast<int>(extraV.size());
      V2.conservativeResize(total, 3);
      for (std::size_t i = 0; i < extraV.size(); ++i) V2.row(nv + static_cast<int>(i)) = extraV[i];
      if (hasColour) {
        C2.conservativeResize(total, 3);
        for (std::size_t i = 0; i < extraC.size(); ++i)
          C2.row(nv + static_cast<int>(i)) = extraC[i];
      }
    }
  }
  mesh.V = std::move(V2);
  mesh.F = std::move(F);
  if (hasColour) scan.colour = std::move(C2);

  // === What remains: non-manifold edges, components, holes.
  const MeshTopology topo(mesh.F, mesh.numVertices());
  report.nonManifoldEdges = static_cast<int>(topo.manifoldness().nonManifoldEdges.size());
  report.components = topo.numComponents();
  report.boundaryLoops = static_cast<int>(topo.boundaryLoops().size());
  for (const auto& loop : topo.boundaryLoops()) {
    double perimeter = 0;
    for (std::size_t i = 0; i < loop.size(); ++i)
      perimeter += (mesh.V.row(loop[i]) - mesh.V.row(loop[(i + 1) % loop.size()])).norm();
    report.largestHolePerimeter = std::max(report.largestHolePerimeter, perimeter);
  }
  if (report.nonManifoldEdges > 0)
    report.warnings.push_back(fmt::format("{}: {} non-manifold edges (more than two faces) remain",
                                          what, report.nonManifoldEdges));
  if (report.components > 1)
    report.warnings.push_back(fmt::format("{}: {} separate components", what, report.components));
  if (report.boundaryLoops > 0)
    report.warnings.push_back(fmt::format("{}: {} holes, the largest with perimeter {:.4g}", what,
                                          report.boundaryLoops, report.largestHolePerimeter));
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace s2p
