#include "segment/vertex_regions.h"

#include <gtest/gtest.h>

#include "core/shapes.h"

namespace s2p {
namespace {

TEST(VertexRegions, EdgesAcrossALineSplitTheGridInTwo) {
  const TriMesh g = makeGrid(10, 10, 1.0, 1.0);
  const MeshTopology topo(g.F, g.numVertices());
  const VertexRegions all = vertexRegions(topo, [](int) { return true; });
  EXPECT_EQ(all.count, 1);
  // Close every edge whose ends lie on either side of x = 0.55.
  auto side = [&](int v) { return g.V(v, 0) < 0.55; };
  const VertexRegions split = vertexRegions(
      topo, [&](int e) { return side(topo.edges()(e, 0)) == side(topo.edges()(e, 1)); });
  ASSERT_EQ(split.count, 2);
  for (int v = 0; v < g.numVertices(); ++v)
    EXPECT_EQ(split.region[v] == split.region[0], side(v) == side(0)) << v;
  // No edge open: every vertex alone.
  EXPECT_EQ(vertexRegions(topo, [](int) { return false; }).count, g.numVertices());
}

}  // namespace
}  // namespace s2p
