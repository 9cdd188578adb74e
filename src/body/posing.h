// Posing a BodyModel: shape blend shapes, forward kinematics, SMPL pose correctives, linear
// blend skinning (formulas in body_model.h), analytic Jacobians for the fitter (paper §4,
// App. A), unposing, standard poses (rest / A / T) and pose JSON files.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <filesystem>
#include <numbers>
#include <vector>

#include "body/body_model.h"
#include "core/tri_mesh.h"

namespace s2p {

// === Shape and pose

Eigen::MatrixX3d shapedTemplate(const BodyModel& model, const Eigen::VectorXd& shape);  // #V×3
Eigen::MatrixX3d restJoints(const BodyModel& model, const Eigen::VectorXd& shape);      // #J×3

struct PosedBody {
  TriMesh mesh;                           // posed vertices, faces of model.rest
  Eigen::MatrixX3d joints;                // #J×3 posed joint positions (translation included)
  std::vector<Eigen::Affine3d> skinning;  // #J, rest (pose-corrected) → posed, translation included
  Eigen::MatrixX3d canonical;             // kNumCanonical×3, posed canonical points
};

// Poses the model. An empty params.shape means β = 0. Throws InputError on size mismatch or
// non-finite parameters.
PosedBody poseBody(const BodyModel& model, const BodyParams& params);

// === Rotations (exposed for the fitter and tests)

// Rodrigues' formula, stable near θ = 0.
Eigen::Matrix3d axisAngleToMatrix(const Eigen::Vector3d& axisAngle);
// Left Jacobian of SO(3): ∂R/∂θ_c · Rᵀ = [J_l(θ)·e_c]× (Gallego & Yezzi 2015), stable near 0.
Eigen::Matrix3d so3LeftJacobian(const Eigen::Vector3d& axisAngle);
// Axis-angle of a rotation matrix (inverse of axisAngleToMatrix, angle in [0, π]).
Eigen::Vector3d matrixToAxisAngle(const Eigen::Matrix3d& R);

// === Jacobians. Parameter order [β (#S) | θ (3#J, joint-major) | t (3)], P = #S + 3#J + 3.

int numPoseParams(const BodyModel& model);  // P
// (3n)×P: rows 3i..3i+2 are ∂v/∂params of vertices[i].
Eigen::MatrixXd posedVertexJacobian(const BodyModel& model, const BodyParams& params,
                                    const std::vector<int>& vertices);
Eigen::MatrixXd posedJointJacobian(const BodyModel& model, const BodyParams& params);  // (3#J)×P
// (3·kNumCanonical)×P, rows in Canonical order.
Eigen::MatrixXd posedCanonicalJacobian(const BodyModel& model, const BodyParams& params);

// Reusable poser: precomputes the regressed joints and their shape directions once, then
// poses and differentiates many times (the fitter's inner loop). Keeps a reference to the
// model, which must outlive it.
class Poser {
 public:
  explicit Poser(const BodyModel& model);

  const BodyModel& model() const { return model_; }
  int numParams() const;
  Eigen::MatrixX3d shapedTemplate(const Eigen::VectorXd& shape) const;  // #V×3
  Eigen::MatrixX3d restJoints(const Eigen::VectorXd& shape) const;      // #J×3
  PosedBody pose(const BodyParams& params) const;
  Eigen::MatrixXd vertexJacobian(const BodyParams& params, const std::vector<int>& vertices) const;
  Eigen::MatrixXd jointJacobian(const BodyParams& params) const;
  Eigen::MatrixXd canonicalJacobian(const BodyParams& params) const;

 private:
  const BodyModel& model_;
  Eigen::MatrixX3d joints0_;        // #J×3 regressed joints at β = 0
  Eigen::MatrixXd jointShapeDirs_;  // (3#J)×#S, row 3j+k: ∂J_jk/∂β
};

// === Unposing

// Inverse of joint `joint`'s skinning transform applied to posed points P (#P×3).
Eigen::MatrixX3d unposePoints(const PosedBody& body, int joint, const Eigen::MatrixX3d& P);
// Per point: inverse of the weight-blended skinning transform (weights #P×#J, rows sum to 1).
Eigen::MatrixX3d unposeSkinned(const PosedBody& body,
                               const Eigen::SparseMatrix<double, Eigen::RowMajor>& weights,
                               const Eigen::MatrixX3d& P);

// Per point: the weight-blended skinning transform applied to rest points P (#P×3), the
// inverse of unposeSkinned (for points that are not the model's vertices: a garment, a body
// carrying a non-rigid fit's detail).
Eigen::MatrixX3d poseSkinned(const PosedBody& body,
                             const Eigen::SparseMatrix<double, Eigen::RowMajor>& weights,
                             const Eigen::MatrixX3d& P);

// Skinning weights of points near a posed body (#P×#J): each point takes those of its closest
// point on `posedBody` (the weights of that face's vertices, blended barycentrically), so that a
// garment can be unposed and posed with the body (unposeSkinned, poseSkinned). posedBody has
// the model's faces.
Eigen::SparseMatrix<double, Eigen::RowMajor> closestPointWeights(const BodyModel& model,
                                                                 const TriMesh& posedBody,
                                                                 const Eigen::MatrixX3d& P);

// === Standard poses

enum class StandardPose { Rest, APose, TPose, DrapePose };

// The drape pose's legs: each turned out by this angle from the vertical in the frontal plane.
inline constexpr double kDrapeLegSpread = 0.14;  // rad, 8°: the ankles ~0.25 m apart, thighs clear

// Arms in the frontal plane, elbows straight, horizontal (T) or 45° below horizontal (A and the
// drape pose); legs at rest, except in the drape pose (the pose patterns are placed and draped
// around: A-pose arms and both legs turned out by kDrapeLegSpread, knees straight, so that no
// sleeve touches the torso and no trouser leg the other); everything else at rest. Computed from
// the canonical shoulder, elbow and wrist joints of the shaped model, so it works whatever the
// source's rest pose is.
BodyPose standardPose(const BodyModel& model, const Eigen::VectorXd& shape, StandardPose which);
inline constexpr double kDrapeArmDown = std::numbers::pi / 4;  // rad: the A-pose's arms, 45°

// The angle of a posed body's upper arm (shoulder → elbow) below the horizontal, measured
// against the body's own up (pelvis → neck): 0 for a T-pose, π/4 for the A-pose, negative
// for an arm raised above the shoulder.
double armAngleBelowHorizontal(const PosedBody& body, bool left);

// The pose a pattern is placed, sewn and draped around for a scan fitted with `fitted`: the
// drape pose, except that an arm scanned higher than its 45° is raised to the scanned angle
// (not above horizontal). A garment scanned with the arms raised has its armpit where the raised
// arm put it, high up the side; sewn around arms 45° down, the tops of its side seams are placed
// inside the arms and the armpit junction cannot close (tpose: 42 stitch pairs open, 51 mm).
struct DrapePoseChoice {
  BodyPose pose;
  double downLeft = kDrapeArmDown, downRight = kDrapeArmDown;  // rad below horizontal
};
DrapePoseChoice drapePoseFor(const BodyModel& model, const Eigen::VectorXd& shape,
                             const PosedBody& fitted);

// A relaxed stance's arms (issue 17): straight in the frontal plane, `down` radians below
// horizontal (default 80°: the arms hang along the sides, the hands by the thighs); the rest of
// the body at rest. A start for fitting scans whose hands touch the thighs.
inline constexpr double kArmsDownAngle = 1.396;  // rad, 80°
BodyPose armsDownPose(const BodyModel& model, const Eigen::VectorXd& shape,
                      double down = kArmsDownAngle);

// === Pose JSON: {"joint_name": [ax, ay, az], ..., "translation": [x, y, z]}

// Joints absent from the file stay at zero. Canonical names ("left_elbow") are accepted for
// joints too. Unknown names → InputError naming them; unreadable file → IoError; not JSON →
// FormatError.
BodyPose readPoseJson(const std::filesystem::path& path, const BodyModel& model);
// Writes every joint by name plus the translation.
void writePoseJson(const std::filesystem::path& path, const BodyModel& model, const BodyPose& pose);

}  // namespace s2p
