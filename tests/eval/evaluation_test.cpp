// evaluate() on a labelled cylinder with known answers: the truth against itself, a prediction
// shifted by a known height, an exactly cut prediction, gap faces, missing boundaries.
#include "eval/evaluation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "eval/eval_fixtures.h"

namespace s2p {
namespace {

using test::CylinderSpec;

constexpr double kH = 0.5;   // true boundary height (on a ring)
constexpr double kD = 0.02;  // shift of the prediction (two rings)

struct Case {
  CylinderSpec spec;
  Truth truth;
  LabelledMesh truthMesh;
  Case() {
    truthMesh = test::labelledCylinder(spec, kH);
    truth.boundaries.push_back(test::circleAt(spec, kH));
  }
  Evaluation run(const LabelledMesh& pred, const std::vector<TrueBoundary>* curves = nullptr,
                 const nlohmann::json* body = nullptr) const {
    EvaluationInput in;
    in.truth = &truth;
    in.truthMesh = &truthMesh;
    in.prediction = &pred;
    in.predictedBoundaries = curves;
    in.predictedBody = body;
    return evaluate(in);
  }
};

TEST(Evaluation, TruthAgainstItselfWithCurves) {
  const Case c;
  const Evaluation e = c.run(c.truthMesh, &c.truth.boundaries);
  EXPECT_TRUE(e.identityTransfer);
  ASSERT_EQ(e.labels.size(), 2u);
  for (const LabelScore& s : e.labels) EXPECT_DOUBLE_EQ(s.iou, 1.0) << toString(s.label);
  EXPECT_DOUBLE_EQ(e.meanIoU, 1.0);
  ASSERT_EQ(e.garmentLabels, std::vector<Label>{Label::Upper});
  EXPECT_DOUBLE_EQ(e.meanGarmentIoU, 1.0);
  // Skin area = perimeter × h of the polygonal prism.
  EXPECT_NEAR(e.label(Label::Skin)->truthArea, test::polygonPerimeter(c.spec) * kH, 1e-12);
  ASSERT_EQ(e.boundaries.size(), 1u);
  const BoundaryScore& b = e.boundaries[0];
  EXPECT_FALSE(b.missing);
  EXPECT_EQ(e.boundarySource, "curves");
  EXPECT_NEAR(b.pooled.mean, 0, 1e-9);
  EXPECT_NEAR(b.pooled.p95, 0, 1e-9);
  EXPECT_NEAR(b.pooled.max, 0, 1e-9);
  EXPECT_NEAR(b.roughness, 1, 1e-9);
  // 1 mm spacing or finer: at least perimeter / 1 mm samples each way.
  EXPECT_GE(b.predToTrue.count, static_cast<int>(test::polygonPerimeter(c.spec) / 1e-3));
}

TEST(Evaluation, TruthAgainstItselfWithLabelEdges) {
  const Case c;
  const Evaluation e = c.run(c.truthMesh);
  EXPECT_EQ(e.boundarySource, "labels");
  ASSERT_EQ(e.boundaries.size(), 1u);
  const BoundaryScore& b = e.boundaries[0];
  ASSERT_FALSE(b.missing);
  EXPECT_NEAR(b.pooled.mean, 0, 1e-9);
  EXPECT_NEAR(b.pooled.p95, 0, 1e-9);
  EXPECT_NEAR(b.roughness, 1, 1e-9);
}

TEST(Evaluation, ShiftedPredictionGivesKnownDistanceAndIoU) {
  const Case c;
  LabelledMesh pred = c.truthMesh;
  pred.faceLabel = test::labelsByHeight(pred.mesh, kH + kD);
  const std::vector<TrueBoundary> curves{test::circleAt(c.spec, kH + kD)};
  const double top = c.spec.height;
  for (const std::vector<TrueBoundary>* given :
       {&curves, static_cast<const std::vector<TrueBoundary>*>(nullptr)}) {
    const Evaluation e = c.run(pred, given);
    const BoundaryScore& b = e.boundaries.at(0);
    ASSERT_FALSE(b.missing);
    for (const DistanceStats* s : {&b.predToTrue, &b.trueToPred, &b.pooled}) {
      EXPECT_NEAR(s->mean, kD, 1e-6);
      EXPECT_NEAR(s->p95, kD, 1e-6);
    }
    EXPECT_NEAR(b.roughness, 1, 1e-9);
    EXPECT_NEAR(e.label(Label::Upper)->iou, (top - kH - kD) / (top - kH), 1e-3);
    EXPECT_NEAR(e.label(Label::Skin)->iou, kH / (kH + kD), 1e-3);
    EXPECT_NEAR(e.meanGarmentIoU, (top - kH - kD) / (top - kH), 1e-3);
  }
}

TEST(Evaluation, CutPredictionTransfersLikeTheIdentity) {
  const Case c;
  // Cut on a ring (h + d): the same labelling as per-face labels on the truth mesh.
  LabelledMesh perFace = c.truthMesh;
  perFace.faceLabel = test::labelsByHeight(perFace.mesh, kH + kD);
  const Evaluation identity = c.run(perFace);
  const LabelledMesh cut = test::cutCylinder(c.spec, kH + kD);
  ASSERT_NE(cut.mesh.numVertices(), c.truthMesh.mesh.numVertices());  // seam duplicated
  const std::vector<TrueBoundary> curves{test::circleAt(c.spec, kH + kD)};
  const Evaluation viaCut = c.run(cut, &curves);
  EXPECT_FALSE(viaCut.identityTransfer);
  EXPECT_TRUE(identity.identityTransfer);
  for (Label l : {Label::Skin, Label::Upper})
    EXPECT_NEAR(viaCut.label(l)->iou, identity.label(l)->iou, 1e-3) << toString(l);
  EXPECT_NEAR(viaCut.unlabelledArea, 0, 1e-12);

  // Cut inside a ring of faces (a true isoline cut): the analytic IoU and distance.
  const double d = 0.0237;
  const LabelledMesh inside = test::cutCylinder(c.spec, kH + d);
  const std::vector<TrueBoundary> insideCurves{test::circleAt(c.spec, kH + d)};
  const Evaluation e = c.run(inside, &insideCurves);
  EXPECT_NEAR(e.label(Label::Upper)->iou, (c.spec.height - kH - d) / (c.spec.height - kH), 1e-6);
  EXPECT_NEAR(e.label(Label::Skin)->iou, kH / (kH + d), 1e-6);
  EXPECT_NEAR(e.boundaries.at(0).pooled.mean, d, 1e-6);
}

TEST(Evaluation, FinerMeshOfTheSameSurfaceTransfersByArea) {
  const Case c;
  // Twice as many rings, same segments: the same surface, other vertices; boundary at 0.515
  // (a ring of the finer mesh, inside a face row of the truth).
  CylinderSpec fine = c.spec;
  fine.rings = 200;
  LabelledMesh pred;
  pred.mesh = makeCylinder(fine.rings, fine.segments, fine.radius, fine.height);
  pred.faceLabel = test::labelsByHeight(pred.mesh, 0.515);
  const Evaluation e = c.run(pred);
  EXPECT_FALSE(e.identityTransfer);
  EXPECT_NEAR(e.label(Label::Upper)->iou, (1 - 0.515) / (1 - kH), 1e-3);
  EXPECT_NEAR(e.boundaries.at(0).pooled.mean, 0.015, 1e-6);
}

TEST(Evaluation, StraddlingFacesAreSampledByArea) {
  const Case c;
  // Another tessellation of (nearly) the same surface: 70 rings, rotated by half a segment, so
  // its faces straddle truth faces; its boundary on ring 36 (y = 36/70).
  CylinderSpec other = c.spec;
  other.rings = 70;
  LabelledMesh pred;
  pred.mesh = makeCylinder(other.rings, other.segments, other.radius, other.height);
  const double turn = std::numbers::pi / other.segments;
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pred.mesh.V = pred.mesh.V * rot.transpose();
  const double y = 36.0 / 70.0;
  pred.faceLabel = test::labelsByHeight(pred.mesh, y);
  const Evaluation e = c.run(pred);
  EXPECT_FALSE(e.identityTransfer);
  EXPECT_NEAR(e.label(Label::Upper)->iou, (1 - y) / (1 - kH), 1e-3);
  EXPECT_NEAR(e.label(Label::Skin)->iou, kH / y, 1e-3);
  EXPECT_LT(e.maxSampleDistance, c.spec.radius * (1 - std::cos(turn)) + 1e-9);  // chord sag
}

TEST(Evaluation, GapFacesAreIgnored) {
  Case c;
  // Rows between 0.2 and 0.3 are gap-filling faces in the truth.
  for (int f = 0; f < c.truthMesh.mesh.numFaces(); ++f) {
    const double y = test::faceCentroid(c.truthMesh.mesh, f).y();
    if (y > 0.2 && y < 0.3) c.truthMesh.faceLabel(f) = static_cast<int>(Label::Gap);
  }
  LabelledMesh pred = c.truthMesh;
  pred.faceLabel = test::labelsByHeight(pred.mesh, kH + kD);
  std::vector<Evaluation> results;
  for (Label asWhat : {Label::Skin, Label::Upper, Label::Gap, Label::Lower}) {
    for (int f = 0; f < pred.mesh.numFaces(); ++f)
      if (c.truthMesh.faceLabel(f) == static_cast<int>(Label::Gap))
        pred.faceLabel(f) = static_cast<int>(asWhat);
    results.push_back(c.run(pred));
  }
  const double perimeter = test::polygonPerimeter(c.spec);
  EXPECT_NEAR(results[0].gapArea, perimeter * 0.1, 1e-12);
  for (const Evaluation& e : results) {
    EXPECT_DOUBLE_EQ(e.label(Label::Upper)->iou, results[0].label(Label::Upper)->iou);
    EXPECT_DOUBLE_EQ(e.label(Label::Skin)->iou, results[0].label(Label::Skin)->iou);
    EXPECT_EQ(e.label(Label::Lower), nullptr);
  }
  // Skin: truth 0.4 of height (0.5 minus the gap), prediction the same plus two rings.
  EXPECT_NEAR(results[0].label(Label::Skin)->iou, 0.4 / 0.42, 1e-9);
}

TEST(Evaluation, HairTheTruthDoesNotLabelIsScoredAsSkin) {
  // Truth: skin below 0.5, upper above (its maker counted hair as skin). The prediction labels
  // the bottom tenth hair and reports the upper|hair part of the boundary as its own pair.
  const Case c;
  LabelledMesh pred = c.truthMesh;
  for (int f = 0; f < pred.mesh.numFaces(); ++f)
    if (test::faceCentroid(pred.mesh, f).y() < 0.1)
      pred.faceLabel(f) = static_cast<int>(Label::Hair);
  std::vector<TrueBoundary> curves = c.truth.boundaries;
  curves[0].a = Label::Upper;
  curves[0].b = Label::Hair;
  const Evaluation e = c.run(pred, &curves);
  EXPECT_EQ(e.foldedIntoSkin, (std::vector<Label>{Label::Hair, Label::Other}));
  EXPECT_NEAR(e.foldedArea, test::polygonPerimeter(c.spec) * 0.1, 1e-9);
  EXPECT_DOUBLE_EQ(e.label(Label::Skin)->iou, 1.0);
  EXPECT_EQ(e.label(Label::Hair), nullptr);
  ASSERT_EQ(e.boundaries.size(), 1u);
  EXPECT_FALSE(e.boundaries[0].missing);  // upper|hair read as upper|skin
  EXPECT_NEAR(e.boundaries[0].pooled.p95, 0, 1e-9);
  // A truth with hair scores it as its own label.
  Case withHair;
  withHair.truthMesh = pred;
  const Evaluation h = withHair.run(pred);
  EXPECT_EQ(h.foldedIntoSkin, std::vector<Label>{Label::Other});
  EXPECT_DOUBLE_EQ(h.label(Label::Hair)->iou, 1.0);
}

TEST(Evaluation, MissingPredictedBoundaryIsReportedNotZero) {
  Case c;
  // Truth: skin | upper at 0.5 and upper | lower at 0.8; the prediction has no lower label.
  for (int f = 0; f < c.truthMesh.mesh.numFaces(); ++f)
    if (test::faceCentroid(c.truthMesh.mesh, f).y() > 0.8)
      c.truthMesh.faceLabel(f) = static_cast<int>(Label::Lower);
  c.truth.boundaries.push_back(test::circleAt(c.spec, 0.8, Label::Upper, Label::Lower));
  const LabelledMesh pred = test::labelledCylinder(c.spec, kH);
  const Evaluation e = c.run(pred);
  ASSERT_EQ(e.boundaries.size(), 2u);
  EXPECT_FALSE(e.boundaries[0].missing);
  EXPECT_TRUE(e.boundaries[1].missing);
  EXPECT_EQ(e.boundaries[1].a, Label::Upper);
  EXPECT_NEAR(e.boundaries[1].trueLength, test::polygonPerimeter(c.spec), 1e-12);
  EXPECT_DOUBLE_EQ(e.label(Label::Lower)->iou, 0.0);
  EXPECT_NEAR(e.meanGarmentIoU, (0.3 / 0.5 + 0.0) / 2, 1e-9);  // upper 0.3 of 0.5, lower 0
  // A one-piece outfit (a dress over leggings, say): the garment mean is the upper IoU only.
  c.truth.garments.push_back({"dress", "dress", Label::Upper, true, {}, 0.5, {}, {}});
  EXPECT_NEAR(c.run(pred).meanGarmentIoU, 0.3 / 0.5, 1e-9);
  const nlohmann::json j = evaluationToJson(e);
  EXPECT_TRUE(j["boundaries"][1]["missing"].get<bool>());
  EXPECT_FALSE(j["boundaries"][1].contains("pooled"));
  EXPECT_NE(formatEvaluation(e).find("missing"), std::string::npos);
}

TEST(Evaluation, JsonAndTableCarryTheFigures) {
  Case withBody;
  LabelledMesh pred = withBody.truthMesh;
  pred.faceLabel = test::labelsByHeight(pred.mesh, kH + kD);
  nlohmann::json body;
  body["canonical"] = {{"pelvis", {0.0, 1.0, 0.0}}};
  nlohmann::json predBody;
  predBody["canonical"] = {{"pelvis", {0.0, 1.004, 0.003}}};
  withBody.truth.body = body;
  const Evaluation e = withBody.run(pred, nullptr, &predBody);
  const nlohmann::json j = evaluationToJson(e);
  EXPECT_NEAR(j["labels"]["upper"]["iou"].get<double>(), 0.96, 1e-9);
  EXPECT_NEAR(j["boundaries"][0]["pooled"]["mean_mm"].get<double>(), 20.0, 1e-3);
  EXPECT_NEAR(j["body"]["mean_error_mm"].get<double>(), 5.0, 1e-9);
  EXPECT_EQ(j["body"]["joints_compared"].get<int>(), 1);
  const std::string table = formatEvaluation(e);
  EXPECT_NE(table.find("0.960"), std::string::npos) << table;
  EXPECT_NE(table.find("20.00"), std::string::npos) << table;
}

TEST(Evaluation, PredictionOffTheTruthSurfaceIsAnInputError) {
  const Case c;
  LabelledMesh far = c.truthMesh;
  far.mesh.V.col(0).array() += 0.5;  // another scan, half a metre away
  EXPECT_THROW(c.run(far), InputError);
  LabelledMesh badLabels = c.truthMesh;
  badLabels.faceLabel(3) = 42;
  EXPECT_THROW(c.run(badLabels), InputError);
  LabelledMesh wrongCount = c.truthMesh;
  wrongCount.faceLabel.conservativeResize(10);
  EXPECT_THROW(c.run(wrongCount), InputError);
  EXPECT_THROW(evaluate(EvaluationInput{}), InputError);
}

}  // namespace
}  // namespace s2p
