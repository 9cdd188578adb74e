#include "segment/vertex_regions.h"

#include <cstdint>

#include "core/row_tree.h"

namespace s2p {

VertexRegions vertexRegions(const MeshTopology& topology, const std::function<bool(int)>& open) {
  const int nV = topology.numVertices();
  std::vector<std::vector<int>> adj(nV);
  for (int e = 0; e < topology.numEdges(); ++e) {
    if (!open(e)) continue;
    const int a = topology.edges()(e, 0), b = topology.edges()(e, 1);
    adj[a].push_back(b);
    adj[b].push_back(a);
  }
  VertexRegions out;
  out.region.assign(nV, -1);
  for (int s = 0; s < nV; ++s) {
    if (out.region[s] >= 0) continue;
    std::vector<int> stack{s};
    out.region[s] = out.count;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int w : adj[v])
        if (out.region[w] < 0) {
          out.region[w] = out.count;
          stack.push_back(w);
        }
    }
    ++out.count;
  }
  return out;
}

std::vector<std::vector<int>> besideSets(const Eigen::MatrixX3d& V, const std::vector<int>& setOf,
                                         int count, double band,
                                         const std::function<bool(int)>& take) {
  std::vector<std::vector<int>> beside(static_cast<size_t>(count));
  std::vector<int> members;
  for (int v = 0; v < static_cast<int>(setOf.size()); ++v)
    if (setOf[v] >= 0) members.push_back(v);
  if (members.empty()) return beside;
  const RowCloud cloud{&V, &members};
  RowTree tree(3, cloud);
  tree.buildIndex();
  for (int v = 0; v < static_cast<int>(setOf.size()); ++v) {
    if (setOf[v] >= 0 || !take(v)) continue;
    std::uint32_t idx = 0;
    double d2 = 0;
    const Eigen::Vector3d p = V.row(v).transpose();
    tree.knnSearch(p.data(), 1, &idx, &d2);
    if (d2 <= band * band) beside[setOf[members[idx]]].push_back(v);
  }
  return beside;
}

}  // namespace s2p
