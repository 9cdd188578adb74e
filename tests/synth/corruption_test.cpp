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

}  // namespace
}  // namespace s2p
