#include "io/cleanup.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>

#include "core/error.h"
#include "core/mesh_topology.h"

namespace s2p {

namespace {

// Open-addressing map from 64-bit keys to ints (keys ≠ kEmpty), linear probing.
class FlatMap {
 public:
  static constexpr std::uint64_t kEmpty = ~0ull;
  explicit FlatMap(std::size_t expected) {
    std::size_t n = 16;
    while (n < 2 * expected) n *= 2;
    keys_.assign(n, kEmpty);
    values_.resize(n);
    mask_ = n - 1;
  }
  // Slot of `key`: values()[slot] is valid when keys_[slot] == key.
  int* find(std::uint64_t key) {
    for (std::size_t i = mix(key) & mask_;; i = (i + 1) & mask_) {
      if (keys_[i] == key) return &values_[i];
      if (keys_[i] == kEmpty) return nullptr;
    }
  }
  // Inserts (key, value) if absent; returns the stored value's address and whether inserted.
  std::pair<int*, bool> insert(std::uint64_t key, int value) {
    for (std::size_t i = mix(key) & mask_;; i = (i + 1) & mask_) {
      if (keys_[i] == key) return {&values_[i], false};
      if (keys_[i] == kEmpty) {
        keys_[i] = key;
        values_[i] = value;
        return {&values_[i], true};
      }
    }
  }

 private:
  static std::size_t mix(std::uint64_t h) {
    h ^= h >> 33;
    h *= 0xFF51AFD7ED558CCDull;
    h ^= h >> 33;
    return static_cast<std::size_t>(h);
  }
  std::vector<std::uint64_t> keys_;
  std::vector<int> values_;
  std::size_t mask_ = 0;
};

// 64-bit key of a grid cell: packed 21 bits per axis when it fits, else hashed. A collision
// only puts two cells in one bucket; the distance test keeps the weld exact.
std::uint64_t cellKey(std::int64_t x, std::int64_t y, std::int64_t z) {
  constexpr std::int64_t kMax = (1 << 21) - 1;
  std::uint64_t key;
  if (x >= 0 && y >= 0 && z >= 0 && x <= kMax && y <= kMax && z <= kMax) {
    key = static_cast<std::uint64_t>(x) | (static_cast<std::uint64_t>(y) << 21) |
          (static_cast<std::uint64_t>(z) << 42);
  } else {
    key = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull;
    key ^= static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full + (key << 6) + (key >> 2);
    key ^= static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull + (key << 6) + (key >> 2);
    key |= 1ull << 63;  // disjoint from packed keys
  }
  return key == FlatMap::kEmpty ? key - 1 : key;
}

// Greedy clustering in vertex order: each vertex joins the first earlier representative
// within `tol`, else becomes one. Grid cells of size 2·tol: the ball of radius tol around a
// point overlaps its own cell and one neighbour per axis, so 8 cells are searched. Returns
// #V representative ids in [0, #reps) and the representatives' original indices.
std::vector<int> weldMap(const Eigen::MatrixX3d& V, double tol, std::vector<int>& repOf) {
  const int nv = static_cast<int>(V.rows());
  std::vector<int> map(nv);
  repOf.clear();
  FlatMap head(static_cast<std::size_t>(nv));  // cell → last representative in it
  std::vector<int> next;                       // representative → previous one in its cell
  if (tol <= 0) {                              // exact copies only: the key is the bit pattern
    std::vector<std::uint64_t> keyOfRep;
    for (int v = 0; v < nv; ++v) {
      std::uint64_t bits[3];
      for (int k = 0; k < 3; ++k) {
        const double x = V(v, k) + 0.0;  // −0 → +0
        std::memcpy(&bits[k], &x, 8);
      }
      const std::uint64_t key = cellKey(
          static_cast<std::int64_t>(bits[0] ^ (bits[1] * 31) ^ (bits[2] * 1000003)), -1, -1);
      int found = -1;
      if (const int* h = head.find(key))
        for (int r = *h; r >= 0; r = next[r])
          if (V.row(repOf[r]) == V.row(v)) {
            found = r;
            break;
          }
      if (found < 0) {
        found = static_cast<int>(repOf.size());
        repOf.push_back(v);
        auto [slot, inserted] = head.insert(key, found);
        next.push_back(inserted ? -1 : *slot);
        *slot = found;
      }
      map[v] = found;
    }
    return map;
  }
  const Eigen::RowVector3d lo = V.colwise().minCoeff();
  const double h = 2 * tol, tol2 = tol * tol;
  for (int v = 0; v < nv; ++v) {
    const Eigen::RowVector3d p = V.row(v);
    std::int64_t c[3], side[3];
    for (int k = 0; k < 3; ++k) {
      const double q = (p[k] - lo[k]) / h;
      const double fl = std::floor(q);
      c[k] = static_cast<std::int64_t>(fl);
      side[k] = q - fl < 0.5 ? -1 : 1;
    }
    int found = -1;
    for (int m = 0; m < 8 && found < 0; ++m) {
      const std::uint64_t key =
          cellKey(c[0] + ((m & 1) ? side[0] : 0), c[1] + ((m & 2) ? side[1] : 0),
                  c[2] + ((m & 4) ? side[2] : 0));
      const int* hd = head.find(key);
      if (!hd) continue;
      for (int r = *hd; r >= 0; r = next[r])
        if ((V.row(repOf[r]) - p).squaredNorm() <= tol2) {
          found = r;
          break;
        }
    }
    if (found < 0) {
      found = static_cast<int>(repOf.size());
      repOf.push_back(v);
      auto [slot, inserted] = head.insert(cellKey(c[0], c[1], c[2]), found);
      next.push_back(inserted ? -1 : *slot);
      *slot = found;
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
    throw InputError(
        fmt::format("{}: weld tolerance {} must be finite and ≥ 0", what, options.weldTolerance));
  const bool hasColour = scan.colour.rows() > 0;
  if (hasColour && scan.colour.rows() != mesh.V.rows())
    throw InputError(
        fmt::format("{}: {} colours for {} vertices", what, scan.colour.rows(), mesh.V.rows()));
  if (scan.texture && scan.texture->FUV.rows() != mesh.F.rows())
    throw InputError(
        fmt::format("{}: {} UV faces for {} faces", what, scan.texture->FUV.rows(), mesh.F.rows()));

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
  std::vector<std::array<int, 4>> sorted;  // (sorted vertex triple, face)
  sorted.reserve(static_cast<std::size_t>(mesh.numFaces()));
  for (int f = 0; f < mesh.numFaces(); ++f) {
    std::array<int, 4> t = {map[mesh.F(f, 0)], map[mesh.F(f, 1)], map[mesh.F(f, 2)], f};
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] ||
        triangleArea(V, t[0], t[1], t[2]) <= areaEps) {
      ++report.degenerateFaces;
      continue;
    }
    std::sort(t.begin(), t.begin() + 3);
    sorted.push_back(t);
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> keep;  // first face of each vertex set, in face order
  keep.reserve(sorted.size());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    if (i > 0 && std::equal(sorted[i].begin(), sorted[i].begin() + 3, sorted[i - 1].begin())) {
      ++report.duplicateFaces;
      continue;
    }
    keep.push_back(sorted[i][3]);
  }
  std::sort(keep.begin(), keep.end());
  if (keep.empty())
    throw InputError(
        fmt::format("{}: no face is left after removing degenerate faces; the mesh "
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

  // === Non-manifold vertices and edges: one copy per fan of faces connected through manifold
  // edges at v.
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
    std::vector<int> fanVertex;
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
      // Faces join only across a manifold edge (v, u) with exactly two faces: the faces of an
      // edge with more (a fin, two sheets touching along an edge) each keep their own fan, so
      // the edge comes apart as the fans get their own copies of v and u.
      for (std::size_t j = 0; j < neighbourFace.size();) {
        std::size_t e = j;
        while (e < neighbourFace.size() && neighbourFace[e].first == neighbourFace[j].first) ++e;
        if (e - j == 2)
          parent[find(neighbourFace[j + 1].second)] = find(neighbourFace[j].second);
        else if (e - j > 2 && v < neighbourFace[j].first)
          ++report.splitNonManifoldEdges;
        j = e;
      }
      // Fan of the first face keeps v; every other fan gets a new copy.
      fanVertex.assign(n, -1);
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
