#include "synth/corruption.h"

#include <meshoptimizer.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numeric>
#include <queue>
#include <random>
#include <string>

#include "core/error.h"
#include "core/mesh_topology.h"

namespace s2p {
namespace {

// Drops faces with keep[f] == false and unreferenced vertices.
HoleCut compact(TriMesh& mesh, const std::vector<bool>& keepFace) {
  HoleCut out;
  std::vector<int> faces;
  for (int f = 0; f < mesh.numFaces(); ++f)
    if (keepFace[f]) faces.push_back(f);
  std::vector<int> newIndex(mesh.numVertices(), -1);
  std::vector<int> vertices;
  for (int f : faces)
    for (int k = 0; k < 3; ++k)
      if (newIndex[mesh.F(f, k)] < 0) newIndex[mesh.F(f, k)] = 0;
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (newIndex[v] == 0) {
      newIndex[v] = static_cast<int>(vertices.size());
      vertices.push_back(v);
    }
  TriMesh m;
  m.V.resize(static_cast<int>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i) m.V.row(int(i)) = mesh.V.row(vertices[i]);
  m.F.resize(static_cast<int>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) m.F(int(i), k) = newIndex[mesh.F(faces[i], k)];
  out.keptFaces = Eigen::Map<Eigen::VectorXi>(faces.data(), static_cast<int>(faces.size()));
  out.keptVertices =
      Eigen::Map<Eigen::VectorXi>(vertices.data(), static_cast<int>(vertices.size()));
  mesh = std::move(m);
  return out;
}

}  // namespace

Eigen::VectorXi decimateMesh(TriMesh& mesh, int targetVertices) {
  if (targetVertices < 100)
    throw InputError("decimation: target of " + std::to_string(targetVertices) +
                     " vertices is below 100; use 0 to keep the level-set mesh");
  const int nv = mesh.numVertices();
  if (targetVertices >= nv) {
    Eigen::VectorXi id(nv);
    for (int v = 0; v < nv; ++v) id[v] = v;
    return id;
  }
  std::vector<float> pos(static_cast<std::size_t>(nv) * 3);
  for (int v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) pos[3 * v + k] = static_cast<float>(mesh.V(v, k));
  std::vector<unsigned> idx(static_cast<std::size_t>(mesh.numFaces()) * 3);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) idx[3 * f + k] = static_cast<unsigned>(mesh.F(f, k));
  // A closed surface has F ≈ 2V faces (plus 2 per boundary loop and handle). meshopt_simplify
  // does not check the link condition: a collapse can fold two faces onto each other (a
  // non-manifold fin; such pairs are dropped) or make two sheets touch along an edge. One retry
  // a little less aggressive; what remains is split apart below.
  const MeshTopology inputTopo(mesh.F, nv);
  const bool inputManifold = inputTopo.manifoldness().isManifold();
  std::size_t targetIndices = static_cast<std::size_t>(targetVertices) * 6;
  TriMesh best;
  HoleCut bestCut;
  for (int attempt = 0; attempt < 2; ++attempt, targetIndices = targetIndices * 21 / 20) {
    std::vector<unsigned> outIdx(idx.size());
    float error = 0;
    const std::size_t n = meshopt_simplify(outIdx.data(), idx.data(), idx.size(), pos.data(), nv,
                                           3 * sizeof(float), targetIndices, 1.0f, 0, &error);
    std::map<std::array<unsigned, 3>, int> seen;
    for (std::size_t i = 0; i < n; i += 3) {
      std::array<unsigned, 3> key{outIdx[i], outIdx[i + 1], outIdx[i + 2]};
      std::sort(key.begin(), key.end());
      ++seen[key];
    }
    TriMesh m;
    m.V = mesh.V;
    m.F.resize(static_cast<int>(n / 3), 3);
    std::vector<bool> keep(n / 3, true);
    for (std::size_t i = 0; i < n; i += 3) {
      std::array<unsigned, 3> key{outIdx[i], outIdx[i + 1], outIdx[i + 2]};
      std::sort(key.begin(), key.end());
      keep[i / 3] = seen[key] == 1;
      for (int k = 0; k < 3; ++k) m.F(static_cast<int>(i / 3), k) = static_cast<int>(outIdx[i + k]);
    }
    HoleCut c = compact(m, keep);
    const MeshTopology topo(m.F, m.numVertices());
    const bool ok =
        !inputManifold || (topo.manifoldness().isManifold() &&
                           topo.boundaryLoops().size() == inputTopo.boundaryLoops().size());
    if (attempt == 0 || ok) best = std::move(m), bestCut = std::move(c);
    if (ok) break;
  }
  mesh = std::move(best);
  if (!inputManifold) return bestCut.keptVertices;
  const Eigen::VectorXi origin = splitNonManifold(mesh);
  separateCoincidentVertices(mesh, 1e-4);
  liftFlatFaces(mesh, 1e-4);
  Eigen::VectorXi kept(origin.size());
  for (int v = 0; v < origin.size(); ++v) kept[v] = bestCut.keptVertices[origin[v]];
  // Splitting can cut off small pockets that a collapse had pinched shut: drop components
  // under 1 % of the faces.
  const MeshTopology split(mesh.F, mesh.numVertices());
  if (split.numComponents() > 1) {
    std::vector<int> size(split.numComponents(), 0);
    for (int f = 0; f < mesh.numFaces(); ++f) ++size[split.faceComponent()[f]];
    std::vector<bool> keepFace(mesh.numFaces());
    for (int f = 0; f < mesh.numFaces(); ++f)
      keepFace[f] = size[split.faceComponent()[f]] * 100 >= mesh.numFaces();
    const HoleCut pocket = compact(mesh, keepFace);
    Eigen::VectorXi k2(pocket.keptVertices.size());
    for (int v = 0; v < k2.size(); ++v) k2[v] = kept[pocket.keptVertices[v]];
    kept = k2;
  }
  return kept;
}

Eigen::VectorXi splitNonManifold(TriMesh& mesh) {
  const int nv = mesh.numVertices(), nf = mesh.numFaces();
  // Corners 3f + k; corners of one vertex joined across every manifold edge form its fans.
  std::vector<int> parent(static_cast<std::size_t>(3) * nf);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto unite = [&](int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  };
  // (edge key, corner of the edge's first vertex) sorted by key groups the faces of each edge.
  struct HalfEdge {
    std::uint64_t key;
    int cornerLo, cornerHi;  // corners at the smaller and the larger vertex index
  };
  std::vector<HalfEdge> half;
  half.reserve(static_cast<std::size_t>(3) * nf);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      const int ca = 3 * f + k, cb = 3 * f + (k + 1) % 3;
      const bool aLow = a < b;
      half.push_back({(static_cast<std::uint64_t>(std::min(a, b)) << 32) |
                          static_cast<std::uint32_t>(std::max(a, b)),
                      aLow ? ca : cb, aLow ? cb : ca});
    }
  std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key != y.key ? x.key < y.key : x.cornerLo < y.cornerLo;
  });
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i;
    while (j < half.size() && half[j].key == half[i].key) ++j;
    if (j - i == 2) {  // a manifold edge joins the fans of both its vertices
      unite(half[i].cornerLo, half[i + 1].cornerLo);
      unite(half[i].cornerHi, half[i + 1].cornerHi);
    }
    i = j;
  }
  // The fan holding a vertex's first corner keeps the vertex; every other fan gets a copy.
  std::vector<int> firstFan(nv, -1);
  std::map<int, int> copyOfFan;
  std::vector<int> origin(nv);
  std::iota(origin.begin(), origin.end(), 0);
  for (int c = 0; c < 3 * nf; ++c) {
    const int v = mesh.F(c / 3, c % 3), fan = find(c);
    if (firstFan[v] < 0) firstFan[v] = fan;
    if (fan == firstFan[v]) continue;
    auto [it, added] = copyOfFan.try_emplace(fan, static_cast<int>(origin.size()));
    if (added) origin.push_back(v);
    mesh.F(c / 3, c % 3) = it->second;
  }
  if (origin.size() > static_cast<std::size_t>(nv)) {
    Eigen::MatrixX3d V(static_cast<Eigen::Index>(origin.size()), 3);
    for (std::size_t v = 0; v < origin.size(); ++v) V.row(int(v)) = mesh.V.row(origin[v]);
    mesh.V = std::move(V);
  }
  return Eigen::Map<Eigen::VectorXi>(origin.data(), static_cast<Eigen::Index>(origin.size()));
}

int separateCoincidentVertices(TriMesh& mesh, double minDistance) {
  const int nv = mesh.numVertices();
  // Vertices bucketed in cells of minDistance; a close pair lies in neighbouring cells.
  std::map<std::array<std::int64_t, 3>, std::vector<int>> cells;
  auto cellOf = [&](int v) {
    std::array<std::int64_t, 3> c{};
    for (int k = 0; k < 3; ++k)
      c[k] = static_cast<std::int64_t>(std::floor(mesh.V(v, k) / minDistance));
    return c;
  };
  for (int v = 0; v < nv; ++v) cells[cellOf(v)].push_back(v);
  std::vector<bool> close(nv, false);
  for (const auto& [c, members] : cells)
    for (int v : members)
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == cells.end()) continue;
            for (int w : it->second)
              if (w != v && (mesh.V.row(v) - mesh.V.row(w)).norm() < minDistance) close[v] = true;
          }
  Eigen::MatrixX3d ring = Eigen::MatrixX3d::Zero(nv, 3);
  Eigen::VectorXi count = Eigen::VectorXi::Zero(nv);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(f, k);
      if (!close[v]) continue;
      ring.row(v) += (mesh.V.row(mesh.F(f, (k + 1) % 3)) + mesh.V.row(mesh.F(f, (k + 2) % 3))) / 2;
      ++count[v];
    }
  int moved = 0;
  const Eigen::MatrixX3d V0 = mesh.V;
  for (int v = 0; v < nv; ++v) {
    if (!close[v] || count[v] == 0) continue;
    const Eigen::RowVector3d d = ring.row(v) / count[v] - V0.row(v);
    if (d.norm() <= 0) continue;
    mesh.V.row(v) = V0.row(v) + minDistance * d.normalized();
    ++moved;
  }
  return moved;
}

int liftFlatFaces(TriMesh& mesh, double lift) {
  // A collapse can leave a triangle with its three corners on one line; a reader drops it as
  // degenerate and opens a hole. Its middle corner (opposite the longest edge) is lifted off the
  // line towards the centroid of its one-ring.
  Eigen::MatrixX3d ring = Eigen::MatrixX3d::Zero(mesh.numVertices(), 3);
  Eigen::VectorXi count = Eigen::VectorXi::Zero(mesh.numVertices());
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      ring.row(mesh.F(f, k)) +=
          (mesh.V.row(mesh.F(f, (k + 1) % 3)) + mesh.V.row(mesh.F(f, (k + 2) % 3))) / 2;
      ++count[mesh.F(f, k)];
    }
  int lifted = 0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::RowVector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                             c = mesh.V.row(mesh.F(f, 2));
    const Eigen::Vector3d e[3] = {(c - b).transpose(), (a - c).transpose(), (b - a).transpose()};
    int longest = 0;
    for (int k = 1; k < 3; ++k)
      if (e[k].norm() > e[longest].norm()) longest = k;
    const double len = e[longest].norm();
    const double area = 0.5 * e[0].cross(e[1]).norm();
    if (len <= 0 || area > 0.25 * lift * len) continue;  // height above the line ≥ lift / 2
    const int v = mesh.F(f, longest);
    const Eigen::RowVector3d d = ring.row(v) / std::max(1, count[v]) - mesh.V.row(v);
    if (d.norm() <= 0) continue;
    mesh.V.row(v) += lift * d.normalized();
    ++lifted;
  }
  return lifted;
}

void addNormalNoise(TriMesh& mesh, double sigma, std::uint64_t seed) {
  if (!(sigma >= 0 && sigma <= 0.05))
    throw InputError("noise: σ = " + std::to_string(sigma) + " m is outside [0, 0.05]");
  if (sigma == 0) return;
  const Eigen::MatrixX3d N = vertexNormals(mesh);
  std::mt19937_64 rng(seed ^ 0xA5A5A5A55A5A5A5Aull);
  std::normal_distribution<double> normal(0, sigma);
  for (int v = 0; v < mesh.numVertices(); ++v) mesh.V.row(v) += normal(rng) * N.row(v);
}

HoleCut cutHoles(TriMesh& mesh, const std::vector<Eigen::Vector3d>& centres, double radius) {
  if (!(radius > 0 && radius <= 0.2))
    throw InputError("holes: radius " + std::to_string(radius) + " m is outside (0, 0.2]");
  const MeshTopology topo(mesh.F, mesh.numVertices());
  if (!topo.isClosed()) throw TopologyError("holes: the mesh must be closed before cutting holes");
  std::vector<bool> keep(mesh.numFaces(), true);
  int holes = 0;
  for (const Eigen::Vector3d& c : centres) {
    int seed = 0;
    (mesh.V.rowwise() - c.transpose()).rowwise().squaredNorm().minCoeff(&seed);
    const Eigen::Vector3d s = mesh.V.row(seed).transpose();
    for (double r = radius; r > 0.2 * radius; r *= 0.8) {
      // Faces reachable from the seed through faces within r of it.
      std::vector<bool> inDisc(mesh.numFaces(), false);
      std::queue<int> todo;
      auto inside = [&](int f) {
        for (int k = 0; k < 3; ++k)
          if ((mesh.V.row(mesh.F(f, k)).transpose() - s).norm() > r) return false;
        return static_cast<bool>(keep[f]);
      };
      for (int f : topo.vertexFaces(seed))
        if (inside(f)) inDisc[f] = true, todo.push(f);
      int count = 0;
      while (!todo.empty()) {
        const int f = todo.front();
        todo.pop();
        ++count;
        for (int k = 0; k < 3; ++k)
          for (int g : topo.edgeFaces(topo.faceEdges()(f, k)))
            if (!inDisc[g] && inside(g)) inDisc[g] = true, todo.push(g);
      }
      if (count == 0) break;
      std::vector<bool> trial = keep;
      for (int f = 0; f < mesh.numFaces(); ++f)
        if (inDisc[f]) trial[f] = false;
      Eigen::MatrixX3i F(std::count(trial.begin(), trial.end(), true), 3);
      for (int f = 0, n = 0; f < mesh.numFaces(); ++f)
        if (trial[f]) F.row(n++) = mesh.F.row(f);
      const MeshTopology t(F, mesh.numVertices());
      if (static_cast<int>(t.boundaryLoops().size()) == holes + 1 &&
          t.manifoldness().isManifold() && t.numComponents() == 1) {
        keep = trial;
        ++holes;
        break;
      }
    }
  }
  HoleCut out = compact(mesh, keep);
  out.holes = holes;
  return out;
}

}  // namespace s2p
