// The parametric body every stage uses: one interface for the built-in mannequin, an MPFB2 /
// MakeHuman folder and a user's SMPL / SMPL-X .npz (paper §4 uses SMPL).
//
// Frame: metres, +Y up, the body faces +Z, the body's LEFT side is on +X (SMPL's convention).
// Posing is linear blend skinning:
//   T(β)    = rest.V + shapeDirs·β                          (shaped template, #V×3)
//   J(β)    = jointRegressor · T(β)                          (rest joints, #J×3)
//   T_P     = T(β) + poseDirs·(R(θ) − I)   (SMPL pose correctives, only when present)
//   G_j(θ)  = world transform of joint j by forward kinematics along `parents`
//   v_i     = Σ_j w_ij · G_j · G_j(0)⁻¹ · T_P,i + t
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

// === Canonical joints and landmarks shared by every source (DESIGN.md "Body model").
enum class Canonical : int {
  Pelvis, Spine, Chest, Neck, Head,
  LeftClavicle, RightClavicle, LeftShoulder, RightShoulder, LeftElbow, RightElbow,
  LeftWrist, RightWrist, LeftHip, RightHip, LeftKnee, RightKnee, LeftAnkle, RightAnkle,
  LeftHandTip, RightHandTip, LeftToeTip, RightToeTip, LeftHeel, RightHeel, HeadTop, Nose,
  Count
};
constexpr int kNumCanonical = static_cast<int>(Canonical::Count);
const char* toString(Canonical c);                       // "pelvis", "left_wrist", ...
std::optional<Canonical> parseCanonical(std::string_view name);

// Where a canonical point comes from: a skeleton joint, or (for surface landmarks such as
// the hand tip, toe tip, heel, head top, nose) a weighted mean of template vertices, which
// then follows shape and pose through the posed vertices.
struct CanonicalDef {
  int joint = -1;                               // skeleton joint index, or −1
  std::vector<std::pair<int, double>> vertices;  // (vertex, weight), weights sum to 1
};

// A shape parameter with a meaning: unit 1 = one "step" described by `description`.
struct ShapeParam {
  std::string name;         // e.g. "chest", "height", "macro-weight"
  std::string description;  // e.g. "chest girth, +1 = +1 cm"
  double min = -5, max = 5;  // range the fitter should stay in
};

struct BodyModel {
  std::string source;                                      // "mannequin", "mpfb2:DIR", "smpl:FILE"
  TriMesh rest;                                            // template at β = 0, θ = 0; closed 2-manifold
  Eigen::MatrixXd shapeDirs;                               // (3#V)×#S, row 3v+k: ∂T_vk/∂β_s
  std::vector<ShapeParam> shapeParams;                     // #S
  Eigen::SparseMatrix<double, Eigen::RowMajor> jointRegressor;  // #J×#V, rows sum to 1
  std::vector<int> parents;                                // #J, parents[j] < j, −1 for the root (j = 0)
  std::vector<std::string> jointNames;                     // #J
  Eigen::SparseMatrix<double, Eigen::RowMajor> weights;    // #V×#J skinning weights, rows sum to 1
  Eigen::MatrixXd poseDirs;                                // (3#V)×9(#J−1) or empty (no correctives)
  std::array<CanonicalDef, kNumCanonical> canonical;

  int numVertices() const { return rest.numVertices(); }
  int numJoints() const { return static_cast<int>(parents.size()); }
  int numShapes() const { return static_cast<int>(shapeDirs.cols()); }
  int jointIndex(std::string_view name) const;  // −1 when absent
  // Throws InputError naming the first inconsistency (sizes, weights not summing to one,
  // parents not topologically ordered, a canonical point undefined).
  void validate() const;
};

// Pose: a local axis-angle per joint (relative to the parent, in the rest frame) and a
// global translation.
struct BodyPose {
  Eigen::MatrixX3d axisAngle;                              // #J×3, radians
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  static BodyPose zero(int numJoints);
};

// Shape and pose together: what the fitter estimates.
struct BodyParams {
  Eigen::VectorXd shape;  // #S
  BodyPose pose;
};

}  // namespace s2p
