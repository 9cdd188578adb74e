// Labellings: majority vote from vertex labels, reading labelled PLYs, and the transfer by area.
#include "eval/labelling.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/eval_fixtures.h"
#include "io/write_mesh.h"
#include "test_support.h"

namespace s2p {
namespace {

TEST(Labelling, FacesTakeTheMajorityVertexLabel) {
  Eigen::MatrixX3i F(3, 3);
  F << 0, 1, 2, 1, 2, 3, 2, 3, 4;
  Eigen::VectorXi vl(5);
  vl << 1, 1, 2, 2, 0;
  const Eigen::VectorXi fl = faceLabelsFromVertexLabels(F, vl);
  EXPECT_EQ(fl(0), 1);  // 1, 1, 2
  EXPECT_EQ(fl(1), 2);  // 1, 2, 2
  EXPECT_EQ(fl(2), 2);  // 2, 2, 0
}

TEST(Labelling, AllDifferentTakesTheSmallestAndBadCodesThrow) {
  Eigen::MatrixX3i F(1, 3);
  F << 0, 1, 2;
  Eigen::VectorXi vl(3);
  vl << 4, 2, 3;
  EXPECT_EQ(faceLabelsFromVertexLabels(F, vl)(0), 2);
  vl << 4, 2, 9;
  EXPECT_THROW(faceLabelsFromVertexLabels(F, vl), InputError);
  vl << 4, 2, -1;
  EXPECT_THROW(faceLabelsFromVertexLabels(F, vl), InputError);
}

TEST(Labelling, ReadsFaceLabelsOrFallsBackToVertexLabels) {
  test::TempDir dir;
  const LabelledMesh lm = test::labelledCylinder({.rings = 10, .segments = 8}, 0.5);
  writePly(dir / "faces.ply", lm.mesh, {.faceLabels = &lm.faceLabel});
  const LabelledMesh back = readLabelledMesh(dir / "faces.ply");
  EXPECT_EQ(back.faceLabel, lm.faceLabel);
  EXPECT_TRUE(back.mesh.V.isApprox(lm.mesh.V));

  // Vertex labels only: vertices on rings 0..5 skin, above upper; the faces of row 5 (two
  // corners on ring 6) become upper, those below skin.
  Eigen::VectorXi vl(lm.mesh.numVertices());
  for (int v = 0; v < vl.size(); ++v) vl(v) = lm.mesh.V(v, 1) > 0.55 ? 1 : 0;
  writePly(dir / "vertices.ply", lm.mesh, {.vertexLabels = &vl});
  const LabelledMesh fromVertices = readLabelledMesh(dir / "vertices.ply");
  EXPECT_EQ(fromVertices.faceLabel, faceLabelsFromVertexLabels(lm.mesh.F, vl));
  int upper = 0;
  for (int f = 0; f < fromVertices.faceLabel.size(); ++f) upper += fromVertices.faceLabel(f) == 1;
  EXPECT_EQ(upper, 8 * 2 * 4 + 8);  // rows 6..9 fully, and row 5's faces with two upper corners
}

TEST(Labelling, BadFilesGiveTypedErrors) {
  test::TempDir dir;
  EXPECT_THROW(readLabelledMesh(dir / "missing.ply"), IoError);
  const TriMesh m = makeGrid(2, 2);
  writePly(dir / "unlabelled.ply", m);
  EXPECT_THROW(readLabelledMesh(dir / "unlabelled.ply"), FormatError);
  Eigen::VectorXi fl = Eigen::VectorXi::Constant(m.numFaces(), 1);
  fl(2) = 17;
  writePly(dir / "badcode.ply", m, {.faceLabels = &fl});
  try {
    readLabelledMesh(dir / "badcode.ply");
    FAIL() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("face 2"), std::string::npos) << e.what();
  }
  test::writeFile(dir / "garbage.ply", "not a ply at all");
  EXPECT_THROW(readLabelledMesh(dir / "garbage.ply"), FormatError);
}

TEST(LabelTransfer, IdentityGivesTheFaceAreas) {
  const LabelledMesh lm = test::labelledCylinder({}, 0.5);
  const LabelTransfer t = transferLabels(lm, lm);
  EXPECT_TRUE(t.identity);
  const Eigen::VectorXd area = faceAreas(lm.mesh);
  for (int f = 0; f < lm.mesh.numFaces(); ++f) {
    EXPECT_DOUBLE_EQ(t.area(f, lm.faceLabel(f)), area(f));
    EXPECT_DOUBLE_EQ(t.area.row(f).sum(), area(f));
  }
  // A copy stored in single precision is still the same mesh.
  LabelledMesh single = lm;
  single.mesh.V = lm.mesh.V.cast<float>().cast<double>();
  EXPECT_TRUE(transferLabels(lm, single).identity);
  single.mesh.V(5, 0) += 1e-4;  // but a moved vertex is not
  EXPECT_FALSE(transferLabels(lm, single).identity);
}

TEST(LabelTransfer, CutFacesLandInTheirScanFaceWithTheirArea) {
  const test::CylinderSpec spec;
  const LabelledMesh truth = test::labelledCylinder(spec, 0.5);
  const LabelledMesh cut = test::cutCylinder(spec, 0.5237);
  const LabelTransfer t = transferLabels(truth, cut);
  EXPECT_FALSE(t.identity);
  EXPECT_EQ(t.unlabelledFaces, 0);
  EXPECT_NEAR(t.maxSampleDistance, 0, 1e-12);
  const Eigen::VectorXd area = faceAreas(truth.mesh);
  // A face of the crossed row (52, between 0.52 and 0.53) carries both labels, split in the
  // ratio of heights; every row sums to the face's area.
  for (int f = 0; f < truth.mesh.numFaces(); ++f) {
    EXPECT_NEAR(t.area.row(f).sum(), area(f), 1e-15);
    const double y = test::faceCentroid(truth.mesh, f).y();
    if (y < 0.52) {
      EXPECT_NEAR(t.area(f, 0), area(f), 1e-15);
    }
    if (y > 0.53) {
      EXPECT_NEAR(t.area(f, 1), area(f), 1e-15);
    }
  }
  const double crossedRowUpper = [&] {
    double s = 0;
    for (int f = 0; f < truth.mesh.numFaces(); ++f) {
      const double y = test::faceCentroid(truth.mesh, f).y();
      if (y > 0.52 && y < 0.53) s += t.area(f, 1);
    }
    return s;
  }();
  EXPECT_NEAR(crossedRowUpper, test::polygonPerimeter(spec) * (0.53 - 0.5237), 1e-12);
}

TEST(LabelTransfer, UncoveredTruthFacesAndFarPredictions) {
  const test::CylinderSpec spec;
  const LabelledMesh truth = test::labelledCylinder(spec, 0.5);
  // A prediction covering only the upper half: the lower half is unlabelled (beyond 1 cm).
  LabelledMesh upperHalf;
  upperHalf.mesh = cutByPlane(truth.mesh, -Eigen::Vector3d::UnitY(), -0.5);
  upperHalf.faceLabel = Eigen::VectorXi::Constant(upperHalf.mesh.numFaces(), 1);
  const LabelTransfer t = transferLabels(truth, upperHalf);
  EXPECT_EQ(t.unlabelledFaces, 2 * spec.segments * 49);  // rows 0..48; row 49 is within 1 cm
  LabelledMesh far = truth;
  far.mesh.V.col(2).array() += 0.05;
  try {
    transferLabels(truth, far);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("another scan"), std::string::npos) << e.what();
  }
  EXPECT_THROW(transferLabels(truth, truth, {.subdivisionLevels = -1}), InputError);
}

}  // namespace
}  // namespace s2p
