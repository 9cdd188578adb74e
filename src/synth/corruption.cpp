#include "synth/corruption.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <map>
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
  // non-manifold fin). Such pairs are dropped; if the result is still not manifold, retry a
  // little less aggressively.
  const MeshTopology inputTopo(mesh.F, nv);
  const bool inputManifold = inputTopo.manifoldness().isManifold();
  std::size_t targetIndices = static_cast<std::size_t>(targetVertices) * 6;
  TriMesh best;
  HoleCut bestCut;
  for (int attempt = 0; attempt < 6; ++attempt, targetIndices = targetIndices * 21 / 20) {
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
    const bool ok = !inputManifold || (topo.manifoldness().isManifold() &&
                                       topo.boundaryLoops().size() ==
                                           inputTopo.boundaryLoops().size());
    if (attempt == 0 || ok) best = std::move(m), bestCut = std::move(c);
    if (ok) break;
  }
  mesh = std::move(best);
  return bestCut.keptVertices;
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
      if (static_cast<int>(t.boundaryLoops().size()) == holes + 1 && t.manifoldness().isManifold() &&
          t.numComponents() == 1) {
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
