#include "segment/vertex_regions.h"

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

}  // namespace s2p
