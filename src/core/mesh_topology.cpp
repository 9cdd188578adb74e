#include "core/mesh_topology.h"

#include <algorithm>
#include <fmt/format.h>
#include <numeric>
#include <utility>

#include "core/error.h"

namespace s2p {
namespace {

// Union-find with path halving and union by index (deterministic roots).
class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    parent_[a] = b;  // the smaller index becomes the root
  }

 private:
  std::vector<int> parent_;
};

// Half-edge h = 3f + k lies opposite corner k of face f and runs F(f,k+1) → F(f,k+2).
inline int heFace(int h) { return h / 3; }
inline int heCorner(int h) { return h % 3; }

}  // namespace

MeshTopology::MeshTopology(const Eigen::MatrixX3i& F, int numVertices)
    : F_(F), numVertices_(numVertices) {
  if (numVertices < 0)
    throw InputError(fmt::format("MeshTopology: negative vertex count {}", numVertices));
  const int nF = static_cast<int>(F.rows());
  for (int f = 0; f < nF; ++f) {
    for (int k = 0; k < 3; ++k)
      if (F(f, k) < 0 || F(f, k) >= numVertices)
        throw InputError(fmt::format(
            "MeshTopology: face {} corner {} references vertex {} but the mesh has {} vertices; "
            "fix the face indices",
            f, k, F(f, k), numVertices));
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0))
      throw TopologyError(fmt::format(
          "MeshTopology: face {} ({}, {}, {}) repeats a vertex; remove degenerate faces first", f,
          F(f, 0), F(f, 1), F(f, 2)));
  }
  const int nH = 3 * nF;

  // === Vertex → faces (CSR, counting sort: faces in increasing order per vertex).
  vertexFaceStart_.assign(numVertices + 1, 0);
  for (int f = 0; f < nF; ++f)
    for (int k = 0; k < 3; ++k) ++vertexFaceStart_[F(f, k) + 1];
  for (int v = 0; v < numVertices; ++v) vertexFaceStart_[v + 1] += vertexFaceStart_[v];
  vertexFaceList_.resize(nH);
  {
    std::vector<int> fill(vertexFaceStart_.begin(), vertexFaceStart_.end() - 1);
    for (int f = 0; f < nF; ++f)
      for (int k = 0; k < 3; ++k) vertexFaceList_[fill[F(f, k)]++] = f;
  }
  numReferencedVertices_ = 0;
  for (int v = 0; v < numVertices; ++v)
    if (vertexFaceStart_[v + 1] > vertexFaceStart_[v]) ++numReferencedVertices_;

  // === Edges: bucket half-edges by their smaller vertex, sort each (small) bucket by the
  // larger vertex; consecutive equal keys are one undirected edge. O(F) plus tiny sorts.
  std::vector<int> bucketStart(numVertices + 1, 0);
  auto lo = [&](int h) { return std::min(F(heFace(h), (heCorner(h) + 1) % 3),
                                         F(heFace(h), (heCorner(h) + 2) % 3)); };
  auto hi = [&](int h) { return std::max(F(heFace(h), (heCorner(h) + 1) % 3),
                                         F(heFace(h), (heCorner(h) + 2) % 3)); };
  for (int h = 0; h < nH; ++h) ++bucketStart[lo(h) + 1];
  for (int v = 0; v < numVertices; ++v) bucketStart[v + 1] += bucketStart[v];
  std::vector<std::pair<int, int>> bucket(nH);  // (larger vertex, half-edge)
  {
    std::vector<int> fill(bucketStart.begin(), bucketStart.end() - 1);
    for (int h = 0; h < nH; ++h) bucket[fill[lo(h)]++] = {hi(h), h};
  }
  faceEdges_.resize(nF, 3);
  std::vector<int> edgeV0, edgeV1;
  edgeV0.reserve(nH / 2 + 1);
  edgeV1.reserve(nH / 2 + 1);
  edgeFaceStart_.clear();
  edgeFaceStart_.reserve(nH / 2 + 2);
  edgeFaceList_.resize(nH);
  int written = 0;
  for (int v = 0; v < numVertices; ++v) {
    auto first = bucket.begin() + bucketStart[v], last = bucket.begin() + bucketStart[v + 1];
    std::sort(first, last);
    for (auto it = first; it != last;) {
      const int e = static_cast<int>(edgeV0.size());
      edgeV0.push_back(v);
      edgeV1.push_back(it->first);
      edgeFaceStart_.push_back(written);
      const int other = it->first;
      for (; it != last && it->first == other; ++it) {
        faceEdges_(heFace(it->second), heCorner(it->second)) = e;
        edgeFaceList_[written++] = heFace(it->second);
      }
    }
  }
  edgeFaceStart_.push_back(written);
  const int nE = static_cast<int>(edgeV0.size());
  edges_.resize(nE, 2);
  for (int e = 0; e < nE; ++e) edges_.row(e) << edgeV0[e], edgeV1[e];
  std::vector<int>().swap(bucketStart);
  std::vector<std::pair<int, int>>().swap(bucket);

  // === Boundary vertices and non-manifold edges.
  boundaryVertex_.assign(numVertices, false);
  for (int e = 0; e < nE; ++e) {
    const int count = edgeFaceCount(e);
    if (count == 1) boundaryVertex_[edges_(e, 0)] = boundaryVertex_[edges_(e, 1)] = true;
    if (count > 2) manifold_.nonManifoldEdges.push_back(e);
  }

  // === Fans: corners (3f + k) of the same vertex joined across each shared edge. A vertex
  // whose corners fall into more than one set is non-manifold (bowtie, touching cones).
  DisjointSets corners(nH);
  auto cornerOf = [&](int f, int v) {
    return 3 * f + (F(f, 0) == v ? 0 : (F(f, 1) == v ? 1 : 2));
  };
  for (int e = 0; e < nE; ++e) {
    const int f0 = edgeFaceList_[edgeFaceStart_[e]];
    for (int i = edgeFaceStart_[e] + 1; i < edgeFaceStart_[e + 1]; ++i) {
      const int f1 = edgeFaceList_[i];
      corners.unite(cornerOf(f0, edges_(e, 0)), cornerOf(f1, edges_(e, 0)));
      corners.unite(cornerOf(f0, edges_(e, 1)), cornerOf(f1, edges_(e, 1)));
    }
  }
  for (int v = 0; v < numVertices; ++v) {
    const int b = vertexFaceStart_[v], end = vertexFaceStart_[v + 1];
    if (end == b) continue;
    const int root = corners.find(cornerOf(vertexFaceList_[b], v));
    for (int i = b + 1; i < end; ++i)
      if (corners.find(cornerOf(vertexFaceList_[i], v)) != root) {
        manifold_.nonManifoldVertices.push_back(v);
        break;
      }
  }

  // === Boundary loops: follow boundary half-edges head to tail; at a vertex with several
  // outgoing boundary half-edges prefer the one in the same fan as the incoming one.
  std::vector<int> outStart(numVertices + 1, 0), outList;
  std::vector<int> boundaryHalfEdges;
  for (int e = 0; e < nE; ++e)
    if (edgeFaceCount(e) == 1) {
      const int f = edgeFaceList_[edgeFaceStart_[e]];
      const int k = faceEdges_(f, 0) == e ? 0 : (faceEdges_(f, 1) == e ? 1 : 2);
      boundaryHalfEdges.push_back(3 * f + k);
    }
  std::sort(boundaryHalfEdges.begin(), boundaryHalfEdges.end());
  auto tail = [&](int h) { return F(heFace(h), (heCorner(h) + 1) % 3); };
  auto head = [&](int h) { return F(heFace(h), (heCorner(h) + 2) % 3); };
  for (int h : boundaryHalfEdges) ++outStart[tail(h) + 1];
  for (int v = 0; v < numVertices; ++v) outStart[v + 1] += outStart[v];
  outList.resize(boundaryHalfEdges.size());
  {
    std::vector<int> fill(outStart.begin(), outStart.end() - 1);
    for (int h : boundaryHalfEdges) outList[fill[tail(h)]++] = h;
  }
  std::vector<char> used(nH, 0);
  for (int h0 : boundaryHalfEdges) {
    if (used[h0]) continue;
    used[h0] = 1;
    std::vector<int> loop{tail(h0)};
    int h = h0;
    while (true) {
      const int w = head(h);
      const int fan = corners.find(3 * heFace(h) + (heCorner(h) + 2) % 3);
      int next = -1;
      for (int i = outStart[w]; i < outStart[w + 1]; ++i) {
        const int c = outList[i];
        if (corners.find(3 * heFace(c) + (heCorner(c) + 1) % 3) == fan) {
          next = c;
          break;
        }
      }
      if (next == h0) break;  // closed
      if (next < 0 || used[next]) {
        next = -1;
        for (int i = outStart[w]; i < outStart[w + 1] && next < 0; ++i)
          if (!used[outList[i]]) next = outList[i];
        if (next < 0) break;  // open chain through a non-manifold vertex
      }
      used[next] = 1;
      loop.push_back(w);
      h = next;
    }
    boundaryLoops_.push_back(std::move(loop));
  }

  // === Face components (through shared vertices, hence also through shared edges).
  DisjointSets faces(nF);
  for (int v = 0; v < numVertices; ++v)
    for (int i = vertexFaceStart_[v] + 1; i < vertexFaceStart_[v + 1]; ++i)
      faces.unite(vertexFaceList_[vertexFaceStart_[v]], vertexFaceList_[i]);
  faceComponent_.resize(nF);
  std::vector<int> label(nF, -1);
  numComponents_ = 0;
  for (int f = 0; f < nF; ++f) {
    const int r = faces.find(f);
    if (label[r] < 0) label[r] = numComponents_++;
    faceComponent_(f) = label[r];
  }
}

std::vector<int> MeshTopology::edgeFaces(int e) const {
  return {edgeFaceList_.begin() + edgeFaceStart_[e], edgeFaceList_.begin() + edgeFaceStart_[e + 1]};
}

int MeshTopology::edgeFaceCount(int e) const { return edgeFaceStart_[e + 1] - edgeFaceStart_[e]; }

std::vector<int> MeshTopology::vertexFaces(int v) const {
  return {vertexFaceList_.begin() + vertexFaceStart_[v],
          vertexFaceList_.begin() + vertexFaceStart_[v + 1]};
}

std::vector<int> MeshTopology::vertexNeighbours(int v) const {
  std::vector<int> out;
  for (int i = vertexFaceStart_[v]; i < vertexFaceStart_[v + 1]; ++i) {
    const int f = vertexFaceList_[i];
    for (int k = 0; k < 3; ++k)
      if (F_(f, k) != v) out.push_back(F_(f, k));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

int MeshTopology::findEdge(int a, int b) const {
  if (a == b || a < 0 || b < 0 || a >= numVertices_ || b >= numVertices_) return -1;
  if (a > b) std::swap(a, b);
  // Edges are sorted by (v0, v1): binary search on v0, then on v1 within the run.
  const int* col0 = edges_.data();
  const int* col1 = edges_.data() + edges_.rows();
  const int n = static_cast<int>(edges_.rows());
  const int first = static_cast<int>(std::lower_bound(col0, col0 + n, a) - col0);
  const int last = static_cast<int>(std::upper_bound(col0 + first, col0 + n, a) - col0);
  const int* it = std::lower_bound(col1 + first, col1 + last, b);
  if (it == col1 + last || *it != b) return -1;
  return static_cast<int>(it - col1);
}

int MeshTopology::eulerCharacteristic() const {
  return numReferencedVertices_ - numEdges() + numFaces();
}

}  // namespace s2p
