#include "core/coarse_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// Icosphere level 6: 40,962 vertices on the unit sphere scaled to a person's size (r = 0.3 m).
const TriMesh& fineSphere() {
  static const TriMesh m = makeIcosphere(6, 0.3);
  return m;
}

TEST(CoarseMesh, CopyHasAboutTheTargetVerticesTakenFromTheFineMesh) {
  const TriMesh& fine = fineSphere();
  const std::optional<CoarseMesh> c = decimatedCopy(fine, 5000);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->mesh.numVertices(), 5000, 1000);
  ASSERT_EQ(c->fineVertex.size(), c->mesh.numVertices());
  for (int v = 0; v < c->mesh.numVertices(); ++v)
    EXPECT_EQ(c->mesh.V.row(v), fine.V.row(c->fineVertex[v])) << v;
  // Still a manifold sphere of the same area (within the chords' shortfall), up to a pinhole or
  // two where a fold or a sliver of the collapses was dropped.
  const MeshTopology topo(c->mesh.F, c->mesh.numVertices());
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(topo.numComponents(), 1);
  EXPECT_LE(topo.boundaryLoops().size(), 5u);
  EXPECT_EQ(topo.eulerCharacteristic(), 2 - static_cast<int>(topo.boundaryLoops().size()));
  EXPECT_NEAR(surfaceArea(c->mesh), surfaceArea(fine), 0.01 * surfaceArea(fine));
}

TEST(CoarseMesh, SmallMeshesAndBadTargetsAreNotDecimated) {
  EXPECT_FALSE(decimatedCopy(fineSphere(), 30000).has_value());  // 40,962 ≤ 1.5 × 30,000
  EXPECT_THROW(decimatedCopy(fineSphere(), 10), InputError);
}

TEST(CoarseMesh, ALinearFieldIsCarriedBackExactlyUpToTheChords) {
  const TriMesh& fine = fineSphere();
  const std::optional<CoarseMesh> c = decimatedCopy(fine, 5000);
  ASSERT_TRUE(c.has_value());
  // φ = y − 0.1 on the copy, carried to the fine mesh: at every fine vertex the value of φ at its
  // closest point on the copy, which lies within the chords' sag (a few tenths of a mm) of it.
  const Eigen::VectorXd coarsePhi = c->mesh.V.col(1).array() - 0.1;
  const CoarseToFine map(c->mesh, fine);
  EXPECT_LT(map.distance().maxCoeff(), 1e-3);
  const Eigen::VectorXd phi = map.carry(coarsePhi);
  ASSERT_EQ(phi.size(), fine.numVertices());
  for (int v = 0; v < fine.numVertices(); ++v)
    ASSERT_NEAR(phi[v], fine.V(v, 1) - 0.1, map.distance()[v] + 1e-12) << v;
  // The copy's own vertices are fine vertices: carried exactly.
  for (int v = 0; v < c->mesh.numVertices(); ++v)
    ASSERT_NEAR(phi[c->fineVertex[v]], coarsePhi[v], 1e-12) << v;
}

}  // namespace
}  // namespace s2p
