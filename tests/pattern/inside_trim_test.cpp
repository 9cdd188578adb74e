#include "pattern/inside_trim.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// A skirt of radius 0.15 from y = 0.3 up to 1.0, its inside seen up to y = 0.45 (radius 0.14),
// folded at the hem; the legs' stand-in a cylinder of radius 0.1.
std::vector<Eigen::Vector2d> skirtProfile(bool withInside) {
  std::vector<Eigen::Vector2d> p;
  if (withInside)
    for (int i = 0; i <= 15; ++i) p.emplace_back(0.14, 0.45 - 0.01 * i);
  for (int i = 0; i <= 70; ++i) p.emplace_back(0.15, 0.30 + 0.01 * i);
  return p;
}

Eigen::VectorXi identity(int n) {
  return Eigen::VectorXi::LinSpaced(n, 0, n - 1);
}

TEST(InsideTrim, TheInsideSeenUnderAHemIsDroppedAndTheOuterFaceKept) {
  const TriMesh body = makeCylinder(60, 48, 0.1, 1.2);
  const TriMesh skirt = makeRevolution(skirtProfile(true), 96);
  // The profile rises at r 0.15 (normals away from the axis) and runs down at r 0.14 inside.
  const std::optional<InsideTrim> t =
      trimInsideSeenThroughOpenings(skirt, identity(skirt.numFaces()), body);
  ASSERT_TRUE(t.has_value());
  const double outer = 2 * M_PI * 0.15 * 0.70, inside = 2 * M_PI * 0.14 * 0.15;
  EXPECT_NEAR(surfaceArea(t->mesh), outer, 0.02 * outer + 0.01);
  EXPECT_NEAR(t->removedArea, inside, 0.02 * inside + 0.01);
  for (int v = 0; v < t->mesh.numVertices(); ++v)
    EXPECT_GT(std::hypot(t->mesh.V(v, 0), t->mesh.V(v, 2)), 0.1399);
  // Every face left is the outer face's; every vertex of the inside went but the fold's.
  int insideVertices = 0;
  for (int v = 0; v < t->mesh.numVertices(); ++v)
    insideVertices +=
        std::hypot(t->mesh.V(v, 0), t->mesh.V(v, 2)) < 0.145 && t->mesh.V(v, 1) > 0.305;
  EXPECT_EQ(insideVertices, 0);
  const MeshTopology topo(t->mesh.F, t->mesh.numVertices());
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(topo.boundaryLoops().size(), 2u);  // the hem and the waist
  ASSERT_EQ(t->faceOrigin.size(), t->mesh.numFaces());
  EXPECT_EQ(t->removedFaces, skirt.numFaces() - t->mesh.numFaces());
}

TEST(InsideTrim, AGarmentWithoutItsInsideIsLeftWhole) {
  const TriMesh body = makeCylinder(60, 48, 0.1, 1.2);
  const TriMesh skirt = makeRevolution(skirtProfile(false), 96);
  EXPECT_FALSE(trimInsideSeenThroughOpenings(skirt, identity(skirt.numFaces()), body).has_value());
  EXPECT_THROW(trimInsideSeenThroughOpenings(skirt, identity(3), body), InputError);
  EXPECT_THROW(trimInsideSeenThroughOpenings(skirt, identity(skirt.numFaces()), TriMesh{}),
               InputError);
}

}  // namespace
}  // namespace s2p
