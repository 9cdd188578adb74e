// Boundary curves from label edges, arc-length sampling, distance statistics, roughness.
#include "eval/boundary_metrics.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/eval_fixtures.h"

namespace s2p {
namespace {

TEST(BoundaryMetrics, SamplesAtUniformArcLength) {
  Eigen::MatrixX3d line(3, 3);
  line << 0, 0, 0, 0.4, 0, 0, 0.4, 0.6, 0;  // open, length 1
  const Eigen::MatrixX3d s = samplePolyline(line, false, 0.3);
  ASSERT_EQ(s.rows(), 5);  // ceil(1 / 0.3) = 4 intervals of 0.25
  EXPECT_TRUE(s.row(1).isApprox(Eigen::RowVector3d(0.25, 0, 0)));
  EXPECT_TRUE(s.row(2).isApprox(Eigen::RowVector3d(0.4, 0.1, 0)));
  EXPECT_TRUE(s.row(4).isApprox(Eigen::RowVector3d(0.4, 0.6, 0)));
  // Closed: the closing segment (length sqrt(0.52)) is sampled too, the start not repeated.
  const double len = 1 + std::sqrt(0.52);
  const Eigen::MatrixX3d c = samplePolyline(line, true, 1e-3);
  EXPECT_EQ(c.rows(), static_cast<Eigen::Index>(std::ceil(len / 1e-3)));
  for (Eigen::Index i = 1; i < c.rows(); ++i)
    EXPECT_LE((c.row(i) - c.row(i - 1)).norm(), 1e-3 + 1e-12);
  EXPECT_THROW(samplePolyline(line, false, 0), InputError);
}

TEST(BoundaryMetrics, DistanceStatistics) {
  Eigen::VectorXd d(101);
  for (int i = 0; i <= 100; ++i) d(i) = i;
  const DistanceStats s = distanceStats(d);
  EXPECT_EQ(s.count, 101);
  EXPECT_DOUBLE_EQ(s.mean, 50);
  EXPECT_DOUBLE_EQ(s.p95, 95);
  EXPECT_DOUBLE_EQ(s.max, 100);
  Eigen::VectorXd two(2);
  two << 0, 10;
  EXPECT_DOUBLE_EQ(distanceStats(two).p95, 9.5);
}

TEST(BoundaryMetrics, PointToCurveDistanceIsExact) {
  TrueBoundary b;
  Eigen::MatrixX3d seg(2, 3);
  seg << 0, 0, 0, 1, 0, 0;
  b.curves.push_back(seg);
  b.closed.push_back(false);
  Eigen::MatrixX3d P(3, 3);
  P << 0.5, 0.3, 0.4,  // above the middle: 0.5
      -0.3, 0.4, 0,    // beyond the start: 0.5
      2, 0, 0;         // beyond the end: 1
  const Eigen::VectorXd d = distanceToCurves(P, b);
  EXPECT_NEAR(d(0), 0.5, 1e-15);
  EXPECT_NEAR(d(1), 0.5, 1e-15);
  EXPECT_NEAR(d(2), 1.0, 1e-15);
}

TEST(BoundaryMetrics, ExtractsTheRingAsOneClosedLoop) {
  const test::CylinderSpec spec;
  const LabelledMesh lm = test::labelledCylinder(spec, 0.5);
  const std::vector<TrueBoundary> b = extractLabelBoundaries(lm);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].a, Label::Skin);
  EXPECT_EQ(b[0].b, Label::Upper);
  ASSERT_EQ(b[0].curves.size(), 1u);
  EXPECT_TRUE(b[0].closed[0]);
  EXPECT_EQ(b[0].curves[0].rows(), spec.segments);
  for (Eigen::Index i = 0; i < b[0].curves[0].rows(); ++i)
    EXPECT_NEAR(b[0].curves[0](i, 1), 0.5, 1e-12);
  EXPECT_NEAR(b[0].length(), test::polygonPerimeter(spec), 1e-12);
}

TEST(BoundaryMetrics, OpenChainOnAStripAndGapEdgesSkipped) {
  // A grid 4×2 cells: bottom row skin, top row upper → one open chain of 5 vertices along y = 0.5.
  LabelledMesh lm;
  lm.mesh = makeGrid(4, 2, 1.0, 1.0);
  lm.faceLabel.resize(lm.mesh.numFaces());
  for (int f = 0; f < lm.mesh.numFaces(); ++f)
    lm.faceLabel(f) = test::faceCentroid(lm.mesh, f).y() > 0.5 ? 1 : 0;
  const std::vector<TrueBoundary> b = extractLabelBoundaries(lm);
  ASSERT_EQ(b.size(), 1u);
  ASSERT_EQ(b[0].curves.size(), 1u);
  EXPECT_FALSE(b[0].closed[0]);
  EXPECT_EQ(b[0].curves[0].rows(), 5);
  EXPECT_NEAR(b[0].length(), 1.0, 1e-12);
  // The same with the upper row as Gap: no boundary at all.
  for (int f = 0; f < lm.mesh.numFaces(); ++f)
    if (lm.faceLabel(f) == 1) lm.faceLabel(f) = static_cast<int>(Label::Gap);
  EXPECT_TRUE(extractLabelBoundaries(lm).empty());
  EXPECT_EQ(extractLabelBoundaries(lm, false).size(), 1u);
  // Lower below gap-filling faces: the rim is the lower garment's boundary with the skin.
  for (int f = 0; f < lm.mesh.numFaces(); ++f)
    if (lm.faceLabel(f) == 0) lm.faceLabel(f) = static_cast<int>(Label::Lower);
  const std::vector<TrueBoundary> rim = extractLabelBoundaries(lm);
  ASSERT_EQ(rim.size(), 1u);
  EXPECT_EQ(rim[0].a, Label::Skin);
  EXPECT_EQ(rim[0].b, Label::Lower);
  EXPECT_NEAR(rim[0].length(), 1.0, 1e-12);
}

TEST(BoundaryMetrics, JaggedLabelEdgeIsRoughTheExactCurveIsNot) {
  const test::CylinderSpec spec;
  const double h = 0.5, dy = spec.height / spec.rings;
  // Odd columns of faces step one ring higher: a zig-zag edge with a vertical step per column.
  LabelledMesh lm;
  lm.mesh = makeCylinder(spec.rings, spec.segments, spec.radius, spec.height);
  lm.faceLabel.resize(lm.mesh.numFaces());
  for (int f = 0; f < lm.mesh.numFaces(); ++f) {
    const int column = (f / 2) % spec.segments;  // makeCylinder: two faces per quad, row-major
    const double threshold = h + (column % 2 ? dy : 0.0);
    lm.faceLabel(f) = test::faceCentroid(lm.mesh, f).y() > threshold ? 1 : 0;
  }
  const TrueBoundary truth = test::circleAt(spec, h + dy / 2);
  const std::vector<TrueBoundary> jagged = extractLabelBoundaries(lm);
  ASSERT_EQ(jagged.size(), 1u);
  ASSERT_EQ(jagged[0].curves.size(), 1u);
  EXPECT_TRUE(jagged[0].closed[0]);
  const BoundaryScore rough = compareBoundary(truth, &jagged[0]);
  const double perimeter = test::polygonPerimeter(spec);
  EXPECT_NEAR(rough.roughness, (perimeter + spec.segments * dy) / perimeter, 1e-9);
  EXPECT_GT(rough.roughness, 1.2);
  // Every jagged point is within half a ring of the true circle, so the distance is small.
  EXPECT_LE(rough.predToTrue.max, dy / 2 + 1e-12);
  const TrueBoundary exact = test::circleAt(spec, h + dy / 2);
  EXPECT_NEAR(compareBoundary(truth, &exact).roughness, 1.0, 1e-12);
}

TEST(BoundaryMetrics, MissingPredictionIsFlagged) {
  const test::CylinderSpec spec;
  const TrueBoundary truth = test::circleAt(spec, 0.5);
  const BoundaryScore none = compareBoundary(truth, nullptr);
  EXPECT_TRUE(none.missing);
  EXPECT_NEAR(none.trueLength, test::polygonPerimeter(spec), 1e-12);
  TrueBoundary empty;
  empty.curves.push_back(Eigen::MatrixX3d(0, 3));
  empty.closed.push_back(false);
  EXPECT_TRUE(compareBoundary(truth, &empty).missing);
}

}  // namespace
}  // namespace s2p
