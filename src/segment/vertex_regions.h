// Connected regions of a mesh's vertices over a chosen set of edges: the flood fill behind the
// iteration's region signs and the removal of small islands after it.
#pragma once

#include <Eigen/Core>
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

// The band beside sets of vertices (setOf: #V, the set of each vertex, −1 for none): for each of
// the `count` sets, the vertices of no set that `take` accepts and whose nearest set vertex,
// within `band` metres, belongs to it (the garment beside a held object or a gap). V: #V×3.
std::vector<std::vector<int>> besideSets(const Eigen::MatrixX3d& V, const std::vector<int>& setOf,
                                         int count, double band,
                                         const std::function<bool(int)>& take);

}  // namespace s2p
