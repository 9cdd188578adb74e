#include "core/mesh_topology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// Torus around the y axis: nu×nv quads split in two, χ = 0.
TriMesh makeTorus(int nu, int nv, double R, double r) {
  TriMesh m;
  m.V.resize(nu * nv, 3);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
      m.V.row(i * nv + j) << (R + r * std::cos(v)) * std::cos(u), r * std::sin(v),
          (R + r * std::cos(v)) * std::sin(u);
    }
  m.F.resize(2 * nu * nv, 3);
  int f = 0;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j;
      const int c = i * nv + (j + 1) % nv, d = ((i + 1) % nu) * nv + (j + 1) % nv;
      m.F.row(f++) << a, b, d;
      m.F.row(f++) << a, d, c;
    }
  return m;
}

TriMesh concat(const TriMesh& a, const TriMesh& b) {
  TriMesh m;
  m.V.resize(a.numVertices() + b.numVertices(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.numFaces() + b.numFaces(), 3);
  m.F << a.F, (b.F.array() + a.numVertices()).matrix();
  return m;
}

// True when the directed edge a→b appears in face f (in its winding order).
bool faceHasDirectedEdge(const Eigen::MatrixX3i& F, int f, int a, int b) {
  for (int k = 0; k < 3; ++k)
    if (F(f, k) == a && F(f, (k + 1) % 3) == b) return true;
  return false;
}

// Every consecutive pair of a loop is a boundary edge traversed in its face's winding.
void expectLoopFollowsFaces(const MeshTopology& topo, const Eigen::MatrixX3i& F,
                            const std::vector<int>& loop) {
  for (size_t i = 0; i < loop.size(); ++i) {
    const int a = loop[i], b = loop[(i + 1) % loop.size()];
    const int e = topo.findEdge(a, b);
    ASSERT_GE(e, 0);
    ASSERT_TRUE(topo.isBoundaryEdge(e));
    EXPECT_TRUE(faceHasDirectedEdge(F, topo.edgeFaces(e)[0], a, b)) << a << "→" << b;
  }
}

TEST(MeshTopology, IcosphereIsClosedWithEulerTwo) {
  const TriMesh s = makeIcosphere(2);
  const MeshTopology topo(s.F, s.numVertices());
  EXPECT_EQ(topo.numVertices(), 162);
  EXPECT_EQ(topo.numEdges(), 480);
  EXPECT_EQ(topo.eulerCharacteristic(), 2);
  EXPECT_TRUE(topo.isClosed());
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(topo.numComponents(), 1);
  EXPECT_EQ(std::count(topo.isBoundaryVertex().begin(), topo.isBoundaryVertex().end(), true), 0);
  // Edges sorted, each edge has two faces, faceEdges points at the edge opposite each corner.
  for (int e = 0; e < topo.numEdges(); ++e) {
    EXPECT_LT(topo.edges()(e, 0), topo.edges()(e, 1));
    EXPECT_EQ(topo.edgeFaceCount(e), 2);
    if (e > 0) {
      const bool sorted = topo.edges()(e - 1, 0) < topo.edges()(e, 0) ||
                          (topo.edges()(e - 1, 0) == topo.edges()(e, 0) &&
                           topo.edges()(e - 1, 1) < topo.edges()(e, 1));
      EXPECT_TRUE(sorted) << e;
    }
  }
  for (int f = 0; f < s.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int e = topo.faceEdges()(f, k);
      const int a = std::min(s.F(f, (k + 1) % 3), s.F(f, (k + 2) % 3));
      const int b = std::max(s.F(f, (k + 1) % 3), s.F(f, (k + 2) % 3));
      EXPECT_EQ(topo.edges()(e, 0), a);
      EXPECT_EQ(topo.edges()(e, 1), b);
      const auto ef = topo.edgeFaces(e);
      EXPECT_NE(std::find(ef.begin(), ef.end(), f), ef.end());
    }
  // The 12 original icosahedron vertices have valence 5, all others 6.
  int valence5 = 0;
  for (int v = 0; v < topo.numVertices(); ++v) {
    const auto n = topo.vertexNeighbours(v);
    EXPECT_EQ(n.size(), topo.vertexFaces(v).size());
    if (n.size() == 5) ++valence5;
  }
  EXPECT_EQ(valence5, 12);
}

TEST(MeshTopology, GridHasOneCounterClockwiseBoundaryLoop) {
  const TriMesh g = makeGrid(4, 3, 2.0, 1.5);
  const MeshTopology topo(g.F, g.numVertices());
  EXPECT_EQ(topo.eulerCharacteristic(), 1);
  ASSERT_EQ(topo.boundaryLoops().size(), 1u);
  const auto& loop = topo.boundaryLoops()[0];
  EXPECT_EQ(loop.size(), 14u);  // 2·(4 + 3) boundary vertices
  expectLoopFollowsFaces(topo, g.F, loop);
  // Surface on the left seen from +z (the faces' normal side): the loop is counter-clockwise,
  // so its signed area equals the grid's area.
  double area2 = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const Eigen::RowVector3d p = g.V.row(loop[i]), q = g.V.row(loop[(i + 1) % loop.size()]);
    area2 += p.x() * q.y() - q.x() * p.y();
  }
  EXPECT_NEAR(0.5 * area2, 3.0, 1e-12);
  int boundaryCount = 0;
  for (int v = 0; v < g.numVertices(); ++v) boundaryCount += topo.isBoundaryVertex()[v];
  EXPECT_EQ(boundaryCount, 14);
  // Interior vertex (1,1) of this triangulation has six neighbours; corners have 2 or 3.
  EXPECT_EQ(topo.vertexNeighbours(1 * 5 + 1).size(), 6u);
  EXPECT_EQ(topo.vertexNeighbours(0), (std::vector<int>{1, 5, 6}));
  EXPECT_GE(topo.findEdge(0, 6), 0);
  EXPECT_EQ(topo.findEdge(6, 0), topo.findEdge(0, 6));
  EXPECT_EQ(topo.findEdge(1, 5), -1);  // the other diagonal is not an edge
  EXPECT_EQ(topo.findEdge(0, 0), -1);
  EXPECT_EQ(topo.findEdge(0, 99), -1);
}

TEST(MeshTopology, CylinderHasTwoLoops) {
  const TriMesh c = makeCylinder(3, 10, 1.0, 2.0);
  const MeshTopology topo(c.F, c.numVertices());
  EXPECT_EQ(topo.eulerCharacteristic(), 0);
  ASSERT_EQ(topo.boundaryLoops().size(), 2u);
  for (const auto& loop : topo.boundaryLoops()) {
    EXPECT_EQ(loop.size(), 10u);
    expectLoopFollowsFaces(topo, c.F, loop);
    // All vertices of a loop are on the same rim.
    for (int v : loop) EXPECT_DOUBLE_EQ(c.V(v, 1), c.V(loop[0], 1));
  }
  EXPECT_NE(c.V(topo.boundaryLoops()[0][0], 1), c.V(topo.boundaryLoops()[1][0], 1));
}

TEST(MeshTopology, TwoDisjointSpheresAreTwoComponents) {
  const TriMesh a = makeIcosphere(1), b = makeUvSphere(6, 8);
  const TriMesh m = concat(a, b);
  const MeshTopology topo(m.F, m.numVertices());
  EXPECT_EQ(topo.numComponents(), 2);
  EXPECT_EQ(topo.eulerCharacteristic(), 4);
  for (int f = 0; f < m.numFaces(); ++f)
    EXPECT_EQ(topo.faceComponent()(f), f < a.numFaces() ? 0 : 1);
}

TEST(MeshTopology, TorusHasEulerZero) {
  const TriMesh t = makeTorus(24, 12, 1.0, 0.3);
  const MeshTopology topo(t.F, t.numVertices());
  EXPECT_EQ(topo.eulerCharacteristic(), 0);
  EXPECT_TRUE(topo.isClosed());
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(topo.numEdges(), 3 * 24 * 12);
}

TEST(MeshTopology, BowtieVertexIsNonManifold) {
  Eigen::MatrixX3i F(2, 3);
  F << 0, 1, 2, 0, 3, 4;
  const MeshTopology topo(F, 5);
  EXPECT_EQ(topo.manifoldness().nonManifoldVertices, std::vector<int>{0});
  EXPECT_TRUE(topo.manifoldness().nonManifoldEdges.empty());
  EXPECT_FALSE(topo.manifoldness().isManifold());
  EXPECT_EQ(topo.numComponents(), 1);  // connected through the shared vertex
  // Each wing is its own triangle loop, not one figure-eight.
  ASSERT_EQ(topo.boundaryLoops().size(), 2u);
  for (const auto& loop : topo.boundaryLoops()) {
    EXPECT_EQ(loop.size(), 3u);
    expectLoopFollowsFaces(topo, F, loop);
  }
}

TEST(MeshTopology, TetrahedraTouchingAtATipAreNonManifold) {
  // Two closed tetrahedra sharing vertex 0: closed, no boundary, one non-manifold vertex.
  Eigen::MatrixX3i F(8, 3);
  F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3,  //
      0, 5, 4, 0, 4, 6, 0, 6, 5, 4, 5, 6;
  const MeshTopology topo(F, 7);
  EXPECT_TRUE(topo.isClosed());
  EXPECT_EQ(topo.manifoldness().nonManifoldVertices, std::vector<int>{0});
  EXPECT_TRUE(topo.manifoldness().nonManifoldEdges.empty());
  EXPECT_EQ(topo.eulerCharacteristic(), 7 - 12 + 8);
}

TEST(MeshTopology, ThreeFacesOnOneEdgeIsNonManifoldEdge) {
  Eigen::MatrixX3i F(3, 3);
  F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  const MeshTopology topo(F, 5);
  const int e = topo.findEdge(0, 1);
  ASSERT_GE(e, 0);
  EXPECT_EQ(topo.edgeFaceCount(e), 3);
  EXPECT_EQ(topo.edgeFaces(e), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(topo.manifoldness().nonManifoldEdges, std::vector<int>{e});
  EXPECT_FALSE(topo.isBoundaryEdge(e));
}

TEST(MeshTopology, IsolatedVerticesDoNotCountInEuler) {
  TriMesh g = makeGrid(2, 2);
  const MeshTopology topo(g.F, g.numVertices() + 3);
  EXPECT_EQ(topo.eulerCharacteristic(), 1);
  EXPECT_TRUE(topo.vertexFaces(g.numVertices()).empty());
  EXPECT_TRUE(topo.vertexNeighbours(g.numVertices() + 2).empty());
}

TEST(MeshTopology, BadFacesThrowTypedErrors) {
  Eigen::MatrixX3i F(1, 3);
  F << 0, 1, 5;
  EXPECT_THROW(MeshTopology(F, 3), InputError);
  F << 0, -1, 2;
  EXPECT_THROW(MeshTopology(F, 3), InputError);
  F << 0, 1, 1;
  EXPECT_THROW(MeshTopology(F, 3), TopologyError);
  EXPECT_THROW(MeshTopology(F, -1), InputError);
  const MeshTopology empty(Eigen::MatrixX3i(0, 3), 0);
  EXPECT_EQ(empty.numEdges(), 0);
  EXPECT_EQ(empty.eulerCharacteristic(), 0);
  EXPECT_EQ(empty.numComponents(), 0);
}

TEST(MeshTopology, TwoMillionFaceGrid_Slow) {
  const TriMesh g = makeGrid(1000, 1000);
  const MeshTopology topo(g.F, g.numVertices());
  EXPECT_EQ(topo.numFaces(), 2'000'000);
  EXPECT_EQ(topo.eulerCharacteristic(), 1);
  ASSERT_EQ(topo.boundaryLoops().size(), 1u);
  EXPECT_EQ(topo.boundaryLoops()[0].size(), 4000u);
  EXPECT_TRUE(topo.manifoldness().isManifold());
}

}  // namespace
}  // namespace s2p
