// A segmentation (and optionally a fitted body) scored against the ground truth of a synthetic
// scan (issue 4 "Metrics", DESIGN.md "How quality is measured"): area-weighted IoU per label,
// boundary distance and roughness per true boundary, canonical-joint error.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "eval/body_metrics.h"
#include "eval/boundary_metrics.h"
#include "eval/labelling.h"
#include "synth/truth.h"

namespace s2p {

struct EvaluationInput {
  const Truth* truth = nullptr;              // required: boundaries and body
  const LabelledMesh* truthMesh = nullptr;   // required: the truth's labelled scan
  const LabelledMesh* prediction = nullptr;  // required: on the scan, a copy or its cut pieces
  // Predicted boundary curves (a segmentation's boundaries.json); nullptr: extracted from the
  // prediction's face labels as chains of mesh edges (extractLabelBoundaries).
  const std::vector<TrueBoundary>* predictedBoundaries = nullptr;
  const nlohmann::json* predictedBody = nullptr;  // body JSON with "canonical"; nullptr: skip
};

struct EvaluationOptions {
  LabelTransferOptions transfer;
  BoundaryMetricOptions boundary;
};

struct LabelScore {
  Label label = Label::Skin;
  double truthArea = 0;     // m², truth faces of this label
  double predArea = 0;      // m², predicted area of this label on non-gap truth faces
  double intersection = 0;  // m²
  double iou = 0;           // intersection / union; 0 when the label is absent from the truth
};

struct Evaluation {
  // Every label present in the truth or the prediction, by code; Gap never (don't-care).
  std::vector<LabelScore> labels;
  double meanIoU = 0;                     // over the labels present in the truth
  std::vector<Label> garmentLabels;       // upper and lower present in the truth (one-piece: upper)
  double meanGarmentIoU = 0;              // over garmentLabels
  double gapArea = 0;                     // m², truth Gap faces left out of every IoU
  // Hair and Other when the truth has no face of them (its maker labelled them skin): the
  // prediction's area and boundaries of these labels are scored as skin.
  std::vector<Label> foldedIntoSkin;
  double foldedArea = 0;                  // m² of predicted area so scored
  double unlabelledArea = 0;              // m², truth area the prediction does not cover
  bool identityTransfer = false;          // the prediction was on the truth mesh itself
  double maxSampleDistance = 0;           // m, prediction → truth surface (0 for the identity)
  std::string boundarySource;             // "curves" (given) or "labels" (extracted)
  std::vector<BoundaryScore> boundaries;  // one per true boundary not involving Gap
  std::optional<BodyScore> body;

  const LabelScore* label(Label l) const;  // nullptr when not listed
};

// IoU per label from the truth's face labels and the predicted area per truth face
// (#F × kNumLabels, transferLabels). Truth faces labelled Gap are left out entirely (paper §5.2
// cuts them off; either side is acceptable), so labelling them anything changes nothing. The
// garment mean is over upper and lower when present, or upper only when onePiece (§5.3).
void scoreLabels(const Eigen::VectorXi& truthLabel, const Eigen::VectorXd& truthArea,
                 const Eigen::MatrixXd& predArea, bool onePiece, Evaluation& out);

// All metrics (hair and held objects the truth does not label are scored as skin, see
// Evaluation::foldedIntoSkin). Missing required inputs or invalid meshes → InputError; a
// prediction not on the truth surface → InputError (transferLabels); a true boundary without
// prediction is reported missing.
Evaluation evaluate(const EvaluationInput& input, const EvaluationOptions& options = {});

// Machine-readable form: lengths and distances in mm, areas in m².
nlohmann::json evaluationToJson(const Evaluation& e);
// Human-readable table (IoU per label, boundaries in mm, body).
std::string formatEvaluation(const Evaluation& e);

}  // namespace s2p
