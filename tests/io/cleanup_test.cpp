#include "io/cleanup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/mesh_topology.h"
#include "io_test_util.h"

namespace s2p {
namespace {

using test::concat;
using test::throwsExactly;

// Every face gets its own three vertices (as assimp imports OBJ per face corner).
TriMesh splitPerCorner(const TriMesh& mesh) {
  TriMesh out;
  out.V.resize(3 * mesh.numFaces(), 3);
  out.F.resize(mesh.numFaces(), 3);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      out.V.row(3 * f + k) = mesh.V.row(mesh.F(f, k));
      out.F(f, k) = 3 * f + k;
    }
  return out;
}

TEST(CleanScan, WeldRestoresClosedSphere) {
  const TriMesh sphere = makeUvSphere(12, 16);
  Scan scan;
  scan.mesh = splitPerCorner(sphere);
  // Noise far below the tolerance (1e-6 of the diagonal) must still weld.
  for (int v = 0; v < scan.mesh.numVertices(); ++v) scan.mesh.V(v, 0) += 1e-10 * (v % 7);
  ASSERT_EQ(MeshTopology(scan.mesh.F, scan.mesh.numVertices()).eulerCharacteristic(),
            sphere.numFaces());  // F disjoint triangles: χ = F
  const CleanupReport r = cleanScan(scan);
  EXPECT_EQ(scan.mesh.numVertices(), sphere.numVertices());
  EXPECT_EQ(scan.mesh.numFaces(), sphere.numFaces());
  EXPECT_EQ(r.weldedVertices, 3 * sphere.numFaces() - sphere.numVertices());
  const MeshTopology topo(scan.mesh.F, scan.mesh.numVertices());
  EXPECT_EQ(topo.eulerCharacteristic(), 2);
  EXPECT_TRUE(topo.isClosed());
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.boundaryLoops, 0);
  EXPECT_EQ(r.degenerateFaces, 0);
  EXPECT_EQ(r.duplicateFaces, 0);
  EXPECT_EQ(r.splitNonManifoldVertices, 0);
}

TEST(CleanScan, ToleranceIsRelativeToDiagonal) {
  // Two triangles whose shared edge copies are 1e-4·diag apart: welded with 1e-3, not 1e-6.
  for (const double scale : {1.0, 1000.0}) {
    TriMesh m;
    m.V.resize(6, 3);
    m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0,  //
        1, 0, 0, 1, 1, 0, 0, 1 + 1.414e-4, 0;
    m.V *= scale;
    m.F.resize(2, 3);
    m.F << 0, 1, 2, 3, 4, 5;
    Scan a, b;
    a.mesh = b.mesh = m;
    EXPECT_EQ(cleanScan(a, {.weldTolerance = 1e-6}).weldedVertices, 1) << scale;
    EXPECT_EQ(cleanScan(b, {.weldTolerance = 1e-3}).weldedVertices, 2) << scale;
    EXPECT_EQ(b.mesh.numVertices(), 4);
  }
}

TEST(CleanScan, WeldAveragesColoursByIncidentArea) {
  // Triangle A (area 0.5) and B (area 1.5) share the edge (1,0,0)–(0,1,0), stored twice.
  TriMesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0,  //
      1, 0, 0, 2, 2, 0, 0, 1, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 3, 4, 5;
  Scan scan;
  scan.mesh = m;
  scan.colour = Eigen::MatrixX3d::Zero(6, 3);
  scan.colour.row(1) << 1, 0, 0;
  scan.colour.row(3) << 0, 0, 1;
  scan.colourSource = ColourSource::Vertex;
  cleanScan(scan);
  ASSERT_EQ(scan.mesh.numVertices(), 4);
  ASSERT_EQ(scan.colour.rows(), 4);
  int shared = -1;
  for (int v = 0; v < 4; ++v)
    if (scan.mesh.V.row(v) == Eigen::RowVector3d(1, 0, 0)) shared = v;
  ASSERT_GE(shared, 0);
  EXPECT_NEAR(scan.colour(shared, 0), 0.25, 1e-12);
  EXPECT_NEAR(scan.colour(shared, 2), 0.75, 1e-12);
}

TEST(CleanScan, DropsDegenerateDuplicateAndUnreferenced) {
  const TriMesh grid = makeGrid(3, 2);
  TriMesh m = grid;
  const int n = grid.numVertices();
  m.V.conservativeResize(n + 2, 3);
  m.V.row(n) = 0.5 * (grid.V.row(0) + grid.V.row(1));  // midpoint of edge 0–1
  m.V.row(n + 1) << 7, 7, 7;                           // never referenced
  const int nf = grid.numFaces();
  m.F.conservativeResize(nf + 4, 3);
  m.F.row(nf) << grid.F(0, 1), grid.F(0, 2), grid.F(0, 0);      // duplicate, rotated
  m.F.row(nf + 1) << grid.F(1, 2), grid.F(1, 1), grid.F(1, 0);  // duplicate, flipped
  m.F.row(nf + 2) << 0, n, 1;                                   // collinear: zero area
  m.F.row(nf + 3) << 2, 2, 3;                                   // repeated index
  Scan scan;
  scan.mesh = m;
  const CleanupReport r = cleanScan(scan);
  EXPECT_EQ(r.duplicateFaces, 2);
  EXPECT_EQ(r.degenerateFaces, 2);
  EXPECT_EQ(r.unreferencedVertices, 2);
  EXPECT_EQ(r.weldedVertices, 0);
  EXPECT_EQ(scan.mesh.V, grid.V);  // vertex order kept
  EXPECT_EQ(scan.mesh.F, grid.F);
  EXPECT_EQ(r.boundaryLoops, 1);
  EXPECT_NEAR(r.largestHolePerimeter, 4.0, 1e-12);  // 1×1 square
}

TEST(CleanScan, SplitsNonManifoldVertexOfTouchingSpheres) {
  // Two unit icospheres touching at one vertex p: after the weld p has two fans.
  const TriMesh a = makeIcosphere(1);
  int top = 0;
  a.V.col(0).maxCoeff(&top);
  const Eigen::RowVector3d p = a.V.row(top);
  TriMesh b = a;
  b.V.rowwise() += 2 * p;
  Scan scan;
  scan.mesh = concat(a, b);
  const CleanupReport r = cleanScan(scan);
  EXPECT_EQ(r.weldedVertices, 1);
  EXPECT_EQ(r.splitNonManifoldVertices, 1);
  EXPECT_EQ(scan.mesh.numVertices(), 2 * a.numVertices());
  EXPECT_EQ(r.components, 2);  // no longer joined through p
  EXPECT_EQ(r.nonManifoldEdges, 0);
  const MeshTopology topo(scan.mesh.F, scan.mesh.numVertices());
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(topo.eulerCharacteristic(), 4);
}

TEST(CleanScan, ReportsNonManifoldEdgeAndHoles) {
  // Three triangles on one edge (a "book"): the non-manifold edge is split, the pages come
  // apart (3 pieces, no non-manifold edge left); open cylinder: 2 holes.
  TriMesh book;
  book.V.resize(5, 3);
  book.V << 0, 0, 0, 0, 1, 0, 1, 0, 0, -1, 0, 0, 0, 0, 1;
  book.F.resize(3, 3);
  book.F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  Scan scan;
  scan.mesh = book;
  const CleanupReport b = cleanScan(scan);
  EXPECT_EQ(b.splitNonManifoldEdges, 1);
  EXPECT_EQ(b.nonManifoldEdges, 0);
  EXPECT_EQ(b.components, 3);
  EXPECT_EQ(scan.mesh.numVertices(), 9);
  // A fin standing on an edge of a closed surface comes off; the surface keeps that edge.
  Scan fin;
  fin.mesh = makeUvSphere(8, 12);
  const int nv = fin.mesh.numVertices(), a = fin.mesh.F(0, 0), c = fin.mesh.F(0, 1);
  fin.mesh.V.conservativeResize(nv + 1, 3);
  fin.mesh.V.row(nv) = 0.5 * (fin.mesh.V.row(a) + fin.mesh.V.row(c)) * 1.2;
  fin.mesh.F.conservativeResize(fin.mesh.numFaces() + 1, 3);
  fin.mesh.F.row(fin.mesh.numFaces() - 1) << a, c, nv;
  const CleanupReport r0 = cleanScan(fin);
  EXPECT_EQ(r0.splitNonManifoldEdges, 1);
  EXPECT_EQ(r0.nonManifoldEdges, 0);
  EXPECT_EQ(r0.components, 2);
  EXPECT_EQ(r0.boundaryLoops, 1);  // the fin's own rim; the sphere stays closed

  const int segments = 24;
  Scan cyl;
  cyl.mesh = makeCylinder(4, segments, 0.3, 1.0);
  const CleanupReport r = cleanScan(cyl);
  EXPECT_EQ(r.boundaryLoops, 2);
  EXPECT_EQ(r.components, 1);
  EXPECT_NEAR(r.largestHolePerimeter, segments * 2 * 0.3 * std::sin(std::numbers::pi / segments),
              1e-9);
}

TEST(CleanScan, KeepsUvIndicesPerCorner) {
  // Two faces whose copies weld; FUV must still point at each corner's own UV row.
  TriMesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.F.resize(3, 3);
  m.F << 0, 1, 2, 3, 4, 5, 0, 0, 1;  // third face degenerate: its FUV row goes too
  Scan scan;
  scan.mesh = m;
  Texture tex;
  tex.UV = Eigen::MatrixX2d::Random(9, 2);
  tex.FUV.resize(3, 3);
  tex.FUV << 0, 1, 2, 3, 4, 5, 6, 7, 8;
  scan.texture = tex;
  cleanScan(scan);
  ASSERT_EQ(scan.mesh.numFaces(), 2);
  EXPECT_EQ(scan.mesh.numVertices(), 4);
  ASSERT_EQ(scan.texture->FUV.rows(), 2);
  EXPECT_EQ(scan.texture->FUV.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(scan.texture->FUV.row(1), Eigen::RowVector3i(3, 4, 5));
}

TEST(CleanScan, BadInputThrowsInputError) {
  Scan nan;
  nan.mesh = makeGrid(1, 1);
  nan.mesh.V(2, 1) = std::nan("");
  EXPECT_TRUE(throwsExactly<InputError>([&] { cleanScan(nan); }));
  Scan flat;  // every face collapses
  flat.mesh = makeGrid(2, 2);
  flat.mesh.V.setZero();
  EXPECT_TRUE(throwsExactly<InputError>([&] { cleanScan(flat); }));
  Scan empty;
  EXPECT_TRUE(throwsExactly<InputError>([&] { cleanScan(empty); }));
}

}  // namespace
}  // namespace s2p
