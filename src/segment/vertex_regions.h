// Connected regions of a mesh's vertices over a chosen set of edges: the flood fill behind the
// iteration's region signs and the removal of small islands after it.
#pragma once

#include <functional>
#include <vector>

#include "core/mesh_topology.h"

namespace s2p {

struct VertexRegions {
  std::vector<int> region;  // #V, region id in [0, count)
  int count = 0;
};

// Vertices joined by the edges e (indices into topology.edges()) for which open(e) is true.
VertexRegions vertexRegions(const MeshTopology& topology, const std::function<bool(int)>& open);

}  // namespace s2p
