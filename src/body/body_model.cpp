#include "body/body_model.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace s2p {

namespace {

constexpr std::array<const char*, kNumCanonical> kCanonicalNames = {
    "pelvis",         "spine",         "chest",
    "neck",           "head",          "left_clavicle",
    "right_clavicle", "left_shoulder", "right_shoulder",
    "left_elbow",     "right_elbow",   "left_wrist",
    "right_wrist",    "left_hip",      "right_hip",
    "left_knee",      "right_knee",    "left_ankle",
    "right_ankle",    "left_hand_tip", "right_hand_tip",
    "left_toe_tip",   "right_toe_tip", "left_heel",
    "right_heel",     "head_top",      "nose"};

// Tolerances on row sums: float32 data (SMPL .npz) sums to one only to ~1e-6.
constexpr double kWeightSumTolerance = 1e-4;
constexpr double kRegressorSumTolerance = 1e-3;

std::string prefix(const BodyModel& m) {
  return "body model '" + m.source + "': ";
}

}  // namespace

const char* toString(Canonical c) {
  const int i = static_cast<int>(c);
  return (i >= 0 && i < kNumCanonical) ? kCanonicalNames[i] : "unknown";
}

std::optional<Canonical> parseCanonical(std::string_view name) {
  for (int i = 0; i < kNumCanonical; ++i)
    if (name == kCanonicalNames[i]) return static_cast<Canonical>(i);
  return std::nullopt;
}

int BodyModel::jointIndex(std::string_view name) const {
  for (int j = 0; j < numJoints(); ++j)
    if (jointNames[j] == name) return j;
  return -1;
}

void BodyModel::validate() const {
  const std::string p = prefix(*this);
  validateMesh(rest, p + "rest mesh");
  const int nv = numVertices(), nj = numJoints();
  if (nj < 1) throw InputError(p + "has no joints");
  if (static_cast<int>(jointNames.size()) != nj)
    throw InputError(p + std::to_string(jointNames.size()) + " joint names for " +
                     std::to_string(nj) + " joints");
  if (parents[0] != -1) throw InputError(p + "joint 0 must be the root (parent −1)");
  for (int j = 1; j < nj; ++j)
    if (parents[j] < 0 || parents[j] >= j)
      throw InputError(p + "joint " + std::to_string(j) + " ('" + jointNames[j] + "') has parent " +
                       std::to_string(parents[j]) + ": parents must precede their children");
  if (shapeDirs.rows() != 3 * nv)
    throw InputError(p + "shapeDirs has " + std::to_string(shapeDirs.rows()) +
                     " rows, expected 3·#V = " + std::to_string(3 * nv));
  if (static_cast<int>(shapeParams.size()) != numShapes())
    throw InputError(p + std::to_string(shapeParams.size()) + " shape parameter names for " +
                     std::to_string(numShapes()) + " shape directions");
  if (!shapeDirs.allFinite()) throw InputError(p + "shapeDirs has non-finite entries");
  if (jointRegressor.rows() != nj || jointRegressor.cols() != nv)
    throw InputError(p + "jointRegressor is " + std::to_string(jointRegressor.rows()) + "×" +
                     std::to_string(jointRegressor.cols()) +
                     ", expected #J×#V = " + std::to_string(nj) + "×" + std::to_string(nv));
  if (weights.rows() != nv || weights.cols() != nj)
    throw InputError(p + "weights are " + std::to_string(weights.rows()) + "×" +
                     std::to_string(weights.cols()) + ", expected #V×#J = " + std::to_string(nv) +
                     "×" + std::to_string(nj));
  for (int j = 0; j < nj; ++j) {
    double sum = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(jointRegressor, j); it;
         ++it)
      sum += it.value();
    if (!(std::abs(sum - 1.0) <= kRegressorSumTolerance))
      throw InputError(p + "jointRegressor row " + std::to_string(j) + " ('" + jointNames[j] +
                       "') sums to " + std::to_string(sum) + ", expected 1");
  }
  for (int v = 0; v < nv; ++v) {
    double sum = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(weights, v); it; ++it) {
      if (!std::isfinite(it.value()) || it.value() < -1e-9)
        throw InputError(p + "skinning weight of vertex " + std::to_string(v) + " on joint " +
                         std::to_string(it.col()) + " is " + std::to_string(it.value()));
      sum += it.value();
    }
    if (!(std::abs(sum - 1.0) <= kWeightSumTolerance))
      throw InputError(p + "skinning weights of vertex " + std::to_string(v) + " sum to " +
                       std::to_string(sum) + ", expected 1");
  }
  if (poseDirs.size() != 0 && (poseDirs.rows() != 3 * nv || poseDirs.cols() != 9 * (nj - 1)))
    throw InputError(p + "poseDirs is " + std::to_string(poseDirs.rows()) + "×" +
                     std::to_string(poseDirs.cols()) + ", expected (3#V)×9(#J−1) = " +
                     std::to_string(3 * nv) + "×" + std::to_string(9 * (nj - 1)) + " or empty");
  if (poseDirs.size() != 0 && !poseDirs.allFinite())
    throw InputError(p + "poseDirs has non-finite entries");
  for (int c = 0; c < kNumCanonical; ++c) {
    const CanonicalDef& d = canonical[c];
    const std::string name = toString(static_cast<Canonical>(c));
    if (d.joint >= nj)
      throw InputError(p + "canonical '" + name + "' refers to missing joint " +
                       std::to_string(d.joint));
    if (d.joint < 0 && d.vertices.empty())
      throw InputError(p + "canonical point '" + name + "' is undefined (no joint, no vertices)");
    if (d.joint < 0) {
      double sum = 0;
      for (const auto& [v, w] : d.vertices) {
        if (v < 0 || v >= nv)
          throw InputError(p + "canonical '" + name + "' refers to missing vertex " +
                           std::to_string(v));
        sum += w;
      }
      if (!(std::abs(sum - 1.0) <= kWeightSumTolerance))
        throw InputError(p + "vertex weights of canonical '" + name + "' sum to " +
                         std::to_string(sum) + ", expected 1");
    }
  }
}

BodyPose BodyPose::zero(int numJoints) {
  BodyPose pose;
  pose.axisAngle = Eigen::MatrixX3d::Zero(numJoints, 3);
  pose.translation.setZero();
  return pose;
}

}  // namespace s2p
