#include "synth/corruption.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"

namespace s2p {
namespace {

TEST(Corruption, DecimationReachesTheTargetAndKeepsInputVertices) {
  TriMesh mesh = makeIcosphere(5, 1.0);  // 10,242 vertices
  const TriMesh input = mesh;
  const Eigen::VectorXi kept = decimateMesh(mesh, 2000);
  EXPECT_NEAR(mesh.numVertices(), 2000, 200);
  ASSERT_EQ(kept.size(), mesh.numVertices());
  for (int v = 0; v < mesh.numVertices(); ++v)
    EXPECT_EQ(mesh.V.row(v), input.V.row(kept[v]));  // vertices stay on the surface
  const MeshTopology topo(mesh.F, mesh.numVertices());
  EXPECT_TRUE(topo.isClosed());
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(topo.eulerCharacteristic(), 2);
  EXPECT_THROW(decimateMesh(mesh, 50), InputError);
}

TEST(Corruption, NoiseMovesAlongTheNormalWithTheAskedSigma) {
  TriMesh mesh = makeIcosphere(4, 1.0);
  TriMesh a = mesh, b = mesh;
  addNormalNoise(a, 0.002, 9);
  addNormalNoise(b, 0.002, 9);
  EXPECT_TRUE(a.V == b.V);  // seeded
  // On a unit sphere the normal is radial: the radius changes by the noise, nothing else.
  const Eigen::VectorXd dr = a.V.rowwise().norm().array() - 1.0;
  const double mean = dr.mean();
  const double sigma = std::sqrt((dr.array() - mean).square().mean());
  EXPECT_NEAR(mean, 0, 3e-4);
  EXPECT_NEAR(sigma, 0.002, 2e-4);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const Eigen::Vector3d n = mesh.V.row(v).normalized();
    const Eigen::Vector3d d = (a.V.row(v) - mesh.V.row(v)).transpose();
    EXPECT_LT((d - d.dot(n) * n).norm(), 0.02 * d.norm() + 1e-12);  // vertex normal ≈ radial
  }
  EXPECT_THROW(addNormalNoise(a, -1, 1), InputError);
}

TEST(Corruption, HolesGiveOneBoundaryLoopEach) {
  TriMesh mesh = makeIcosphere(4, 1.0);
  const std::vector<Eigen::Vector3d> centres = {
      {0, 1.2, 0}, {0, -1.2, 0}, {1.2, 0, 0}, {-1.2, 0, 0}};
  const HoleCut cut = cutHoles(mesh, centres, 0.2);
  EXPECT_EQ(cut.holes, 4);
  const MeshTopology topo(mesh.F, mesh.numVertices());
  EXPECT_EQ(topo.boundaryLoops().size(), 4u);
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(topo.eulerCharacteristic(), 2 - 4);
  EXPECT_EQ(cut.keptFaces.size(), mesh.numFaces());
  // Every removed face was within the radius of a centre's nearest vertex.
  EXPECT_LT(mesh.numFaces(), makeIcosphere(4, 1.0).numFaces());
  EXPECT_THROW(cutHoles(mesh, centres, 0.2), TopologyError);  // no longer closed
}

// Two closed tetrahedra (on vertices 0,1,2,3 and 0,1,4,5) glued along the edge 0-1, which
// has four faces: splitting gives two closed manifold components with 0 and 1 duplicated.
TEST(Corruption, SplitNonManifoldSeparatesSheetsTouchingAlongAnEdge) {
  TriMesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5, -1, -1, 0.5, -0.5, 0.2;
  m.F.resize(8, 3);
  m.F << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2,  // tetrahedron A
      0, 1, 4, 1, 5, 4, 0, 4, 5, 0, 5, 1;     // tetrahedron B
  ASSERT_FALSE(MeshTopology(m.F, m.numVertices()).manifoldness().isManifold());
  const TriMesh before = m;
  const Eigen::VectorXi origin = splitNonManifold(m);
  const MeshTopology topo(m.F, m.numVertices());
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_TRUE(topo.isClosed());
  EXPECT_EQ(topo.numComponents(), 2);
  EXPECT_EQ(m.numVertices(), before.numVertices() + 2);  // vertices 0 and 1 duplicated
  for (int v = 0; v < m.numVertices(); ++v) EXPECT_EQ(m.V.row(v), before.V.row(origin[v]));
  for (int f = 0; f < m.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(origin[m.F(f, k)], before.F(f, k));
  // The copies are moved apart, each into its own sheet, beyond any reader's weld tolerance.
  EXPECT_EQ(separateCoincidentVertices(m, 1e-4), 4);
  for (int v : {0, 1}) {
    int copy = -1;
    for (int w = before.numVertices(); w < m.numVertices(); ++w)
      if (origin[w] == v) copy = w;
    ASSERT_GE(copy, 0);
    EXPECT_GT((m.V.row(v) - m.V.row(copy)).norm(), 1e-4);
    EXPECT_LT((m.V.row(v) - before.V.row(v)).norm(), 1.01e-4);
  }
  // A manifold mesh is left as it was.
  TriMesh sphere = makeIcosphere(2);
  const TriMesh copy = sphere;
  EXPECT_EQ(splitNonManifold(sphere).size(), copy.numVertices());
  EXPECT_EQ(sphere.F, copy.F);
}

}  // namespace
}  // namespace s2p
