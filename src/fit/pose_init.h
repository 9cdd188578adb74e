// Pose initialisation without a network (replaces the paper's OpenPose on seven renders, §4):
// the extremities of the scan by geodesic farthest points from the chest (head, hands, feet;
// left and right from the facing direction), wrists, elbows, ankles and knees as centroids of
// geodesic rings at the body's own limb lengths from the extremities, then inverse kinematics
// (Ceres) placing the canonical joints there.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "body/body_model.h"
#include "core/tri_mesh.h"

namespace s2p {

// A 3D point for a canonical joint, e.g. found on the scan or read from a keypoint file.
struct JointTarget {
  Canonical joint;
  Eigen::Vector3d position;
  double weight = 1;
};

struct Extremities {
  Eigen::Vector3d headTop, leftHand, rightHand, leftFoot, rightFoot;  // scan points
  std::vector<JointTarget>
      targets;  // joints found along the limbs (wrists, elbows, ankles, knees, head top)
};

struct PoseInitOptions {
  double minSeparation = 0.25;  // metres: geodesic distance between two extremities
  double ringWidth = 0.03;      // metres: width of the geodesic band whose centroid is a joint
  double posePrior = 0.01;      // IK regulariser on |θ|, root excluded
  int maxIterations = 100;
};

// Finds the five extremities of a scan in the standard frame (metres, +Y up, facing +Z, the
// person's left on +X) and the limb joints along them. `model` and `shape` give the limb
// lengths (scaled to the scan's height). Throws InputError when five extremities separated by
// `minSeparation` do not exist (limbs merged with the body, not a person).
Extremities findExtremities(const TriMesh& scan, const BodyModel& model,
                            const Eigen::VectorXd& shape, const PoseInitOptions& options = {});

// Inverse kinematics: the pose and translation that put the canonical points of the shaped
// body at the targets (least squares, Ceres LM with the analytic canonical Jacobian), starting
// from `start`.
BodyParams solveInverseKinematics(const BodyModel& model, const BodyParams& start,
                                  const std::vector<JointTarget>& targets,
                                  const PoseInitOptions& options = {});

// solveInverseKinematics from the rest pose moved onto the targets' centroid. Throws InputError
// for fewer than 4 targets.
BodyParams poseFromTargets(const BodyModel& model, const Eigen::VectorXd& shape,
                           const std::vector<JointTarget>& targets,
                           const PoseInitOptions& options = {});

// findExtremities then poseFromTargets.
BodyParams initialisePose(const TriMesh& scan, const BodyModel& model,
                          const Eigen::VectorXd& shape = {}, const PoseInitOptions& options = {});

// `pose` (its translation ignored) moved so that the body's area centroid lies on the scan's: a
// start for the fit that needs nothing found on the scan.
BodyParams poseOnScan(const TriMesh& scan, const BodyModel& model, const BodyPose& pose,
                      const Eigen::VectorXd& shape = {});

// The fallback when no pose can be found (BSE's translateTo): the rest pose with the body's
// area centroid on the scan's.
BodyParams restPoseOnScan(const TriMesh& scan, const BodyModel& model,
                          const Eigen::VectorXd& shape = {});

}  // namespace s2p
