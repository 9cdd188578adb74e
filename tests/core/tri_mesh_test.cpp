#include "core/tri_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

TEST(TriMesh, GridAreaAndNormals) {
  const TriMesh grid = makeGrid(4, 3, 2.0, 1.5);
  EXPECT_EQ(grid.numVertices(), 20);
  EXPECT_EQ(grid.numFaces(), 24);
  EXPECT_NEAR(surfaceArea(grid), 3.0, 1e-12);
  const Eigen::MatrixX3d N = vertexNormals(grid);
  for (int v = 0; v < N.rows(); ++v) EXPECT_NEAR(N(v, 2), 1.0, 1e-12);
}

TEST(TriMesh, IcosphereConvergesToSphereArea) {
  const TriMesh s = makeIcosphere(5, 2.0);
  EXPECT_EQ(s.numVertices(), 10 * 1024 + 2);
  EXPECT_NEAR(surfaceArea(s), 4 * std::numbers::pi * 4.0, 0.01 * 16 * std::numbers::pi);
  // Outward normals: normal · position > 0.
  const Eigen::MatrixX3d N = vertexNormals(s);
  for (int v = 0; v < s.numVertices(); ++v) EXPECT_GT(N.row(v).dot(s.V.row(v)), 0.0);
}

TEST(TriMesh, ValidateRejectsNonFiniteAndEmpty) {
  TriMesh m = makeGrid(1, 1);
  EXPECT_NO_THROW(validateMesh(m, "grid"));
  m.V(2, 1) = std::nan("");
  EXPECT_THROW(validateMesh(m, "grid"), InputError);
  TriMesh empty;
  EXPECT_THROW(validateMesh(empty, "empty"), InputError);
  TriMesh bad = makeGrid(1, 1);
  bad.F(0, 0) = 17;
  EXPECT_THROW(validateMesh(bad, "bad"), InputError);
}

TEST(TriMesh, CutByPlaneOpensAHole) {
  const TriMesh s = makeIcosphere(3);
  const TriMesh cut = cutByPlane(s, Eigen::Vector3d::UnitY(), 0.8);
  EXPECT_LT(cut.numFaces(), s.numFaces());
  EXPECT_LT(cut.numVertices(), s.numVertices());
  EXPECT_LE(cut.V.col(1).maxCoeff(), 1.0);
}

}  // namespace
}  // namespace s2p
