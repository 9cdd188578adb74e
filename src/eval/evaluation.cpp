#include "eval/evaluation.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.h"

namespace s2p {
namespace {

nlohmann::json statsToJson(const DistanceStats& s) {
  return {{"count", s.count},
          {"mean_mm", 1e3 * s.mean},
          {"p95_mm", 1e3 * s.p95},
          {"max_mm", 1e3 * s.max}};
}

const TrueBoundary* findPair(const std::vector<TrueBoundary>& list, Label a, Label b) {
  for (const TrueBoundary& tb : list)
    if ((tb.a == a && tb.b == b) || (tb.a == b && tb.b == a)) return &tb;
  return nullptr;
}

}  // namespace

const LabelScore* Evaluation::label(Label l) const {
  for (const LabelScore& s : labels)
    if (s.label == l) return &s;
  return nullptr;
}

void scoreLabels(const Eigen::VectorXi& truthLabel, const Eigen::VectorXd& truthArea,
                 const Eigen::MatrixXd& predArea, bool onePiece, Evaluation& out) {
  if (truthLabel.size() != truthArea.size() || predArea.rows() != truthLabel.size() ||
      predArea.cols() != kNumLabels)
    throw InputError(
        fmt::format("scoreLabels: {} truth labels, {} areas and a {}×{} predicted "
                    "area matrix do not match",
                    truthLabel.size(), truthArea.size(), predArea.rows(), predArea.cols()));
  const int gap = static_cast<int>(Label::Gap);
  Eigen::VectorXd tArea = Eigen::VectorXd::Zero(kNumLabels), pArea = tArea, inter = tArea;
  out.gapArea = out.unlabelledArea = 0;
  for (Eigen::Index f = 0; f < truthLabel.size(); ++f) {
    const int t = truthLabel(f);
    if (!isValidLabel(t)) throw InputError(fmt::format("truth face {} has label {}", f, t));
    if (t == gap) {
      out.gapArea += truthArea(f);
      continue;
    }
    tArea(t) += truthArea(f);
    pArea += predArea.row(f).transpose();
    inter(t) += predArea(f, t);
    const double uncovered = truthArea(f) - predArea.row(f).sum();
    if (uncovered > 1e-9 * truthArea(f)) out.unlabelledArea += uncovered;  // not rounding
  }
  out.labels.clear();
  out.garmentLabels.clear();
  double sum = 0, garmentSum = 0;
  int present = 0;
  for (int l = 0; l < kNumLabels; ++l) {
    if (l == gap || (tArea(l) <= 0 && pArea(l) <= 0)) continue;
    LabelScore s;
    s.label = static_cast<Label>(l);
    s.truthArea = tArea(l);
    s.predArea = pArea(l);
    s.intersection = inter(l);
    const double uni = s.truthArea + s.predArea - s.intersection;
    s.iou = uni > 0 ? s.intersection / uni : 0;
    out.labels.push_back(s);
    if (tArea(l) > 0) {
      sum += s.iou;
      ++present;
      if (s.label == Label::Upper || (s.label == Label::Lower && !onePiece)) {
        out.garmentLabels.push_back(s.label);
        garmentSum += s.iou;
      }
    }
  }
  out.meanIoU = present ? sum / present : 0;
  out.meanGarmentIoU =
      out.garmentLabels.empty() ? 0 : garmentSum / static_cast<double>(out.garmentLabels.size());
}

namespace {

// Hair and Other when no truth face carries them.
std::vector<Label> foldedLabels(const Eigen::VectorXi& truthLabel) {
  std::vector<Label> out;
  for (Label l : {Label::Hair, Label::Other})
    if (!(truthLabel.array() == static_cast<int>(l)).any()) out.push_back(l);
  return out;
}

// The predicted boundaries with the folded labels read as skin; pairs that become skin|skin go.
std::vector<TrueBoundary> foldBoundaries(const std::vector<TrueBoundary>& pred,
                                         const std::vector<Label>& folded) {
  const auto fold = [&](Label l) {
    return std::find(folded.begin(), folded.end(), l) != folded.end() ? Label::Skin : l;
  };
  std::vector<TrueBoundary> out;
  for (const TrueBoundary& b : pred) {
    Label a = fold(b.a), c = fold(b.b);
    if (a == c) continue;  // hair|skin on a truth without hair: no boundary
    if (c < a) std::swap(a, c);
    auto it = std::find_if(out.begin(), out.end(),
                           [&](const TrueBoundary& t) { return t.a == a && t.b == c; });
    if (it == out.end()) {
      out.push_back({a, c, {}, {}});
      it = out.end() - 1;
    }
    it->curves.insert(it->curves.end(), b.curves.begin(), b.curves.end());
    it->closed.insert(it->closed.end(), b.closed.begin(), b.closed.end());
  }
  return out;
}

}  // namespace

Evaluation evaluate(const EvaluationInput& in, const EvaluationOptions& opt) {
  if (!in.truth || !in.truthMesh || !in.prediction)
    throw InputError("evaluate: the truth, its labelled mesh and the prediction are required");
  Evaluation out;
  LabelTransfer transfer = transferLabels(*in.truthMesh, *in.prediction, opt.transfer);
  out.identityTransfer = transfer.identity;
  out.maxSampleDistance = transfer.maxSampleDistance;
  // Hair and held objects that the truth does not label (a scan whose maker counted hair as
  // skin) are scored as the skin they are there; a garment taken for them still loses its area.
  out.foldedIntoSkin = foldedLabels(in.truthMesh->faceLabel);
  const int skin = static_cast<int>(Label::Skin);
  for (Label l : out.foldedIntoSkin) {
    const int c = static_cast<int>(l);
    out.foldedArea += transfer.area.col(c).sum();
    transfer.area.col(skin) += transfer.area.col(c);
    transfer.area.col(c).setZero();
  }
  scoreLabels(in.truthMesh->faceLabel, faceAreas(in.truthMesh->mesh), transfer.area,
              in.truth->hasOnePiece(), out);

  std::vector<TrueBoundary> extracted;
  const std::vector<TrueBoundary>* pred = in.predictedBoundaries;
  out.boundarySource = pred ? "curves" : "labels";
  if (!pred) {
    extracted = extractLabelBoundaries(*in.prediction);
    pred = &extracted;
  }
  std::vector<TrueBoundary> folded;
  if (!out.foldedIntoSkin.empty()) {
    folded = foldBoundaries(*pred, out.foldedIntoSkin);
    pred = &folded;
  }
  for (const TrueBoundary& tb : in.truth->boundaries) {
    if (tb.a == Label::Gap || tb.b == Label::Gap) continue;
    out.boundaries.push_back(compareBoundary(tb, findPair(*pred, tb.a, tb.b), opt.boundary));
  }
  if (in.predictedBody) out.body = compareBodies(in.truth->body, *in.predictedBody);
  return out;
}

nlohmann::json evaluationToJson(const Evaluation& e) {
  nlohmann::json j;
  nlohmann::json labels = nlohmann::json::object();
  for (const LabelScore& s : e.labels)
    labels[toString(s.label)] = {{"iou", s.iou},
                                 {"truth_area_m2", s.truthArea},
                                 {"pred_area_m2", s.predArea},
                                 {"intersection_m2", s.intersection}};
  j["labels"] = labels;
  j["mean_iou"] = e.meanIoU;
  nlohmann::json garments = nlohmann::json::array();
  for (Label l : e.garmentLabels) garments.push_back(toString(l));
  j["garment_labels"] = garments;
  j["mean_garment_iou"] = e.meanGarmentIoU;
  j["gap_area_m2"] = e.gapArea;
  nlohmann::json folded = nlohmann::json::array();
  for (Label l : e.foldedIntoSkin) folded.push_back(toString(l));
  j["scored_as_skin"] = folded;
  j["scored_as_skin_area_m2"] = e.foldedArea;
  j["unlabelled_area_m2"] = e.unlabelledArea;
  j["identity_transfer"] = e.identityTransfer;
  j["max_sample_distance_mm"] = 1e3 * e.maxSampleDistance;
  j["boundary_source"] = e.boundarySource;
  nlohmann::json bs = nlohmann::json::array();
  for (const BoundaryScore& b : e.boundaries) {
    nlohmann::json jb = {{"labels", {toString(b.a), toString(b.b)}},
                         {"missing", b.missing},
                         {"true_length_mm", 1e3 * b.trueLength}};
    if (!b.missing) {
      jb["pred_length_mm"] = 1e3 * b.predLength;
      jb["roughness"] = b.roughness;
      jb["pred_to_true"] = statsToJson(b.predToTrue);
      jb["true_to_pred"] = statsToJson(b.trueToPred);
      jb["pooled"] = statsToJson(b.pooled);
    }
    bs.push_back(jb);
  }
  j["boundaries"] = bs;
  if (e.body) {
    nlohmann::json joints = nlohmann::json::object();
    for (const JointError& je : e.body->joints) joints[je.name] = 1e3 * je.error;
    j["body"] = {{"joints_compared", e.body->count},
                 {"mean_error_mm", 1e3 * e.body->meanError},
                 {"max_error_mm", 1e3 * e.body->maxError},
                 {"worst_joint", e.body->worstJoint},
                 {"joint_error_mm", joints},
                 {"missing_joints", e.body->missing}};
  }
  return j;
}

std::string formatEvaluation(const Evaluation& e) {
  std::string s;
  s += fmt::format("{:<14}{:>12}{:>12}{:>9}\n", "label", "truth m²", "pred m²", "IoU");
  for (const LabelScore& l : e.labels)
    s += fmt::format("{:<14}{:>12.4f}{:>12.4f}{:>9.3f}{}\n", toString(l.label), l.truthArea,
                     l.predArea, l.iou, l.truthArea > 0 ? "" : "  (not in the truth)");
  std::string names;
  for (Label l : e.garmentLabels) names += (names.empty() ? "" : ", ") + std::string(toString(l));
  s += fmt::format("mean IoU {:.3f}; garments ({}) {:.3f}\n", e.meanIoU,
                   names.empty() ? "none" : names, e.meanGarmentIoU);
  if (e.gapArea > 0) s += fmt::format("gap faces left out: {:.4f} m²\n", e.gapArea);
  if (e.foldedArea > 0) {
    std::string names;
    for (Label l : e.foldedIntoSkin)
      names += (names.empty() ? "" : ", ") + std::string(toString(l));
    s += fmt::format("predicted {} not in the truth, scored as skin: {:.4f} m²\n", names,
                     e.foldedArea);
  }
  if (e.unlabelledArea > 0)
    s += fmt::format("truth area the prediction does not cover: {:.4f} m²\n", e.unlabelledArea);
  s += fmt::format("\nboundaries (mm; predicted curves from {})\n",
                   e.boundarySource == "curves" ? "the given curves" : "the label edges");
  s += fmt::format("{:<14}{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}\n", "pair", "pred→true", "p95",
                   "true→pred", "p95", "mean", "p95", "rough");
  for (const BoundaryScore& b : e.boundaries) {
    const std::string pair = fmt::format("{}|{}", toString(b.a), toString(b.b));
    if (b.missing) {
      s += fmt::format("{:<14}  missing (no predicted curve; true length {:.1f} mm)\n", pair,
                       1e3 * b.trueLength);
      continue;
    }
    s += fmt::format("{:<14}{:>10.2f}{:>10.2f}{:>10.2f}{:>10.2f}{:>10.2f}{:>10.2f}{:>10.3f}\n",
                     pair, 1e3 * b.predToTrue.mean, 1e3 * b.predToTrue.p95, 1e3 * b.trueToPred.mean,
                     1e3 * b.trueToPred.p95, 1e3 * b.pooled.mean, 1e3 * b.pooled.p95, b.roughness);
  }
  if (e.boundaries.empty()) s += "(the truth has no boundaries)\n";
  if (e.body)
    s += fmt::format("\nbody: {} canonical joints, mean error {:.1f} mm, max {:.1f} mm ({})\n",
                     e.body->count, 1e3 * e.body->meanError, 1e3 * e.body->maxError,
                     e.body->worstJoint);
  return s;
}

}  // namespace s2p
