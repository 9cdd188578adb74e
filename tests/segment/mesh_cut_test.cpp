#include "segment/mesh_cut.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/shapes.h"

namespace s2p {
namespace {

TEST(MeshCut, AreasOfTwoPartsSumToTheOriginal) {
  const TriMesh s = makeIcosphere(3);
  const Eigen::VectorXd phi =
      s.V * Eigen::Vector3d(0.3, 1.0, -0.2) - Eigen::VectorXd::Constant(s.numVertices(), 0.17);
  const CutResult cut = cutAlongIsoline(s, phi);
  const double a = surfaceArea(s), an = surfaceArea(cut.negative.mesh),
               ap = surfaceArea(cut.positive.mesh);
  EXPECT_NEAR(an + ap, a, 1e-12 * a);
  EXPECT_GT(an, 0.3 * a);
  EXPECT_GT(ap, 0.3 * a);
  // Per original face too.
  Eigen::VectorXd perFace = Eigen::VectorXd::Zero(s.numFaces());
  for (const CutPart* part : {&cut.negative, &cut.positive}) {
    const Eigen::VectorXd fa = faceAreas(part->mesh);
    for (int f = 0; f < part->mesh.numFaces(); ++f) perFace[part->faceOrigin[f]] += fa[f];
  }
  EXPECT_LT((perFace - faceAreas(s)).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(MeshCut, VertexOriginsReproducePositionsAndFacesLieInTheirOriginalFace) {
  const TriMesh s = makeIcosphere(3);
  const Eigen::VectorXd phi =
      s.V.col(0) + 0.5 * s.V.col(2) - Eigen::VectorXd::Constant(s.numVertices(), 0.2);
  const CutResult cut = cutAlongIsoline(s, phi);
  for (const CutPart* part : {&cut.negative, &cut.positive}) {
    for (int v = 0; v < part->mesh.numVertices(); ++v) {
      const VertexOrigin& o = part->vertexOrigin[v];
      const Eigen::Vector3d p = (1 - o.t) * s.V.row(o.a) + o.t * s.V.row(o.b);
      EXPECT_EQ((p - part->mesh.V.row(v).transpose()).norm(), 0.0);
      if (!o.isOriginal()) {
        EXPECT_NEAR((1 - o.t) * phi[o.a] + o.t * phi[o.b], 0, 1e-12);
      }
    }
    for (int f = 0; f < part->mesh.numFaces(); ++f) {
      const Eigen::Vector3d c =
          (part->mesh.V.row(part->mesh.F(f, 0)) + part->mesh.V.row(part->mesh.F(f, 1)) +
           part->mesh.V.row(part->mesh.F(f, 2))) /
          3;
      const int g = part->faceOrigin[f];
      const Eigen::Vector3d b =
          planeBarycentric(c, s.V.row(s.F(g, 0)), s.V.row(s.F(g, 1)), s.V.row(s.F(g, 2)));
      EXPECT_GT(b.minCoeff(), -1e-12);
    }
  }
}

TEST(MeshCut, CutBoundaryIsTheIsolineAndPartsAreDisks) {
  const TriMesh s = makeIcosphere(3);
  const Eigen::VectorXd phi = s.V.col(1) - Eigen::VectorXd::Constant(s.numVertices(), 0.35);
  const CutResult cut = cutAlongIsoline(s, phi);
  ASSERT_EQ(cut.isoline.curves.size(), 1u);
  const Eigen::MatrixX3d iso = cut.isoline.positions();
  for (const CutPart* part : {&cut.negative, &cut.positive}) {
    const MeshTopology topo(part->mesh.F, part->mesh.numVertices());
    EXPECT_TRUE(topo.manifoldness().isManifold());
    EXPECT_EQ(topo.eulerCharacteristic(), 1);  // a disk
    ASSERT_EQ(topo.boundaryLoops().size(), 1u);
    const auto& loop = topo.boundaryLoops()[0];
    EXPECT_EQ(loop.size(), static_cast<size_t>(iso.rows()));
    double len = 0;
    for (size_t i = 0; i < loop.size(); ++i) {
      const int v = loop[i];
      EXPECT_FALSE(part->vertexOrigin[v].isOriginal());
      const double d = (iso.rowwise() - part->mesh.V.row(v)).rowwise().norm().minCoeff();
      EXPECT_LT(d, 1e-15);
      len += (part->mesh.V.row(loop[(i + 1) % loop.size()]) - part->mesh.V.row(v)).norm();
    }
    EXPECT_NEAR(len, cut.isoline.length(), 1e-12);
  }
}

TEST(MeshCut, CylinderCutBetweenRingsHasExactAreaBelow) {
  const int segments = 24;
  const double r = 0.2, h = 1.0;
  const TriMesh cyl = makeCylinder(10, segments, r, h);
  const Eigen::VectorXd phi = cyl.V.col(1) - Eigen::VectorXd::Constant(cyl.numVertices(), 0.45);
  const CutResult cut = cutAlongIsoline(cyl, phi);
  const double chord = 2 * r * std::sin(M_PI / segments);
  EXPECT_NEAR(surfaceArea(cut.negative.mesh), segments * chord * 0.45, 1e-12);
  EXPECT_NEAR(surfaceArea(cut.positive.mesh), segments * chord * 0.55, 1e-12);
  const MeshTopology topo(cut.negative.mesh.F, cut.negative.mesh.numVertices());
  EXPECT_EQ(topo.boundaryLoops().size(), 2u);
  EXPECT_NEAR(cut.isoline.length(), segments * chord, 1e-12);
}

TEST(MeshCut, ZeroAtVerticesCountsAsPositiveAndKeepsAreasExact) {
  const TriMesh g = makeGrid(10, 6, 1.0, 1.0);
  const Eigen::VectorXd phi = g.V.col(0) - Eigen::VectorXd::Constant(g.numVertices(), 0.5);
  const CutResult cut = cutAlongIsoline(g, phi);  // column x = 0.5 is exactly zero
  EXPECT_NEAR(surfaceArea(cut.negative.mesh), 0.5, 1e-12);
  EXPECT_NEAR(surfaceArea(cut.positive.mesh), 0.5, 1e-12);
  EXPECT_LE(cut.negative.mesh.V.col(0).maxCoeff(), 0.5 + 1e-15);
  EXPECT_GE(cut.positive.mesh.V.col(0).minCoeff(), 0.5 - 1e-15);
}

}  // namespace
}  // namespace s2p
