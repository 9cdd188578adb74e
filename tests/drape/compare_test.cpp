#include "drape/compare.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

TEST(CompareMeshes, ParallelPlanesAreTheirOffsetApartBothWays) {
  TriMesh a = makeGrid(20, 20, 0.5, 0.5);
  TriMesh b = makeGrid(13, 17, 0.5, 0.5);  // other meshing, same square
  b.V.col(2).array() += 0.01;
  const MeshComparison c = compareMeshes(a, b);
  for (const SurfaceDistanceStats* s : {&c.aToB, &c.bToA}) {
    EXPECT_NEAR(s->meanMm, 10.0, 1e-6);
    EXPECT_NEAR(s->p95Mm, 10.0, 1e-6);
    EXPECT_NEAR(s->maxMm, 10.0, 1e-6);
  }
  EXPECT_EQ(c.distanceA.size(), a.numVertices());
  EXPECT_NEAR(c.distanceA.maxCoeff(), 0.01, 1e-9);
}

TEST(CompareMeshes, ConcentricSpheresDifferByTheirRadii) {
  const TriMesh a = makeIcosphere(5, 1.0);
  const TriMesh b = makeIcosphere(5, 1.02);
  const MeshComparison c = compareMeshes(a, b);
  // Vertices lie on their sphere; the other's faces sag inwards by up to ≈ 0.26 mm at level 5
  // (edge ≈ 0.039 r): A → B is a little under 20 mm, B → A a little over.
  EXPECT_NEAR(c.aToB.meanMm, 20.0, 0.4);
  EXPECT_NEAR(c.bToA.meanMm, 20.0, 0.4);
  EXPECT_NEAR(c.aToB.p95Mm, 20.0, 0.4);
  EXPECT_LE(c.maxMm(), 20.4);
  EXPECT_GE(c.aToB.maxMm, 19.6);
}

TEST(CompareMeshes, APartlyUncoveredMeshHasItsLargestDistanceWhereItSticksOut) {
  // A: 1 m square; B: its left half. A's right edge is 0.5 m from B, B is on A everywhere.
  const TriMesh a = makeGrid(20, 20, 1.0, 1.0);
  const TriMesh b = makeGrid(10, 20, 0.5, 1.0);
  const MeshComparison c = compareMeshes(a, b);
  EXPECT_NEAR(c.aToB.maxMm, 500.0, 1e-6);
  EXPECT_NEAR(c.aToB.worst.x(), 1.0, 1e-12);
  EXPECT_NEAR(c.bToA.maxMm, 0.0, 1e-9);
  // Area-weighted mean of max(0, x − 0.5) over the unit square: 0.125 m.
  EXPECT_NEAR(c.aToB.meanMm, 125.0, 1.0);
}

TEST(CompareMeshes, EmptyMeshIsAnInputError) {
  EXPECT_THROW(compareMeshes(TriMesh{}, makeGrid(2, 2)), InputError);
  EXPECT_THROW(topDropMm(TriMesh{}, makeGrid(2, 2), Eigen::Vector3d::UnitY()), InputError);
}

TEST(TopDrop, ATubeSlidDownHangsByHowFarItSlid) {
  // The scanned tube: y ∈ [0, 0.3]. The draped one, meshed otherwise and a little wider, slid
  // 120 mm down: the top drops by that, whatever the meshing (rings 3 and 5 mm apart).
  const TriMesh scanned = makeCylinder(100, 64, 0.15, 0.3);
  TriMesh draped = makeCylinder(60, 48, 0.16, 0.3);
  EXPECT_NEAR(topDropMm(draped, scanned, Eigen::Vector3d::UnitY()), 0.0, 5.0);
  draped.V.col(1).array() -= 0.12;
  EXPECT_NEAR(topDropMm(draped, scanned, Eigen::Vector3d::UnitY()), 120.0, 5.0);
  // Its top higher than scanned: negative. Sideways (x) the slide does not count: the draped
  // tube reaches 10 mm further (radius 0.16 against 0.15).
  EXPECT_NEAR(topDropMm(scanned, draped, Eigen::Vector3d::UnitY()), -120.0, 5.0);
  EXPECT_NEAR(topDropMm(draped, scanned, Eigen::Vector3d::UnitX()), -10.0, 1.5);
}

}  // namespace
}  // namespace s2p
