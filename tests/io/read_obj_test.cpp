#include "io/read_obj.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "io/write_mesh.h"
#include "io_test_util.h"
#include "test_support.h"

namespace s2p {
namespace {

using test::TempDir;
using test::throwsExactly;

// Two triangles that touch only at one corner, where each has its own vertex at the same
// position: a manifold mesh whose two corner vertices a weld by position would join into one
// non-manifold vertex (the case of a cut garment written and read back).
TriMesh twoTrianglesTouchingAtACorner() {
  TriMesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0,  //
      0, 0, 0, -1, 0, 0, 0, -1, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 3, 4, 5;
  return m;
}

TEST(ReadObj, KeepsTheFilesVerticesAsTheyAreIndexed) {
  TempDir dir;
  const TriMesh m = twoTrianglesTouchingAtACorner();
  writeObj(dir / "m.obj", m);
  const TriMesh back = readObjGeometry(dir / "m.obj");
  ASSERT_EQ(back.numVertices(), 6);  // the coincident corners stay two vertices
  EXPECT_TRUE(back.F == m.F);
  EXPECT_TRUE(back.V.isApprox(m.V));
  EXPECT_TRUE(MeshTopology(back.F, back.numVertices()).manifoldness().isManifold());
}

TEST(ReadObj, ReadsPolygonsReferencesAndNegativeIndices) {
  const TriMesh m = parseObjGeometry(
      "# a quad and a triangle\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 0.5 0.5 0.5\nvt 0 0\n"
      "f 1/1 2/1 3/1 4/1\n"
      "f -4//1 -2 -1\n",
      "test");
  ASSERT_EQ(m.numVertices(), 4);
  ASSERT_EQ(m.numFaces(), 3);
  EXPECT_EQ(m.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(m.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(m.F.row(2), Eigen::RowVector3i(0, 2, 3));
}

TEST(ReadObj, GarbageIsAFormatError) {
  EXPECT_TRUE(throwsExactly<FormatError>([] { parseObjGeometry("v 0 0 0\nf 1 2 3\n", "t"); }));
  EXPECT_TRUE(throwsExactly<FormatError>([] { parseObjGeometry("v 0 0\n", "t"); }));
  EXPECT_TRUE(throwsExactly<FormatError>([] { parseObjGeometry("v 0 0 0\nf 1 x 1\n", "t"); }));
  EXPECT_TRUE(throwsExactly<FormatError>([] { parseObjGeometry("\x89PNG garbage", "t"); }));
  EXPECT_TRUE(throwsExactly<IoError>([] { readObjGeometry("/nonexistent/m.obj"); }));
}

}  // namespace
}  // namespace s2p
