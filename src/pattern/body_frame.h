// The posed body as the pattern stage sees it: its canonical joints, an anatomical frame (up,
// left, front) and the limbs as polylines, so that garment openings and seams can be named by
// where they lie on the body (a cuff is an opening on an arm, away from the shoulder).
#pragma once

#include <Eigen/Core>
#include <string>

#include "body/body_model.h"
#include "core/tri_mesh.h"

namespace s2p {

enum class Limb { Torso, Neck, LeftArm, RightArm, LeftLeg, RightLeg };
const char* toString(Limb limb);
inline bool isArm(Limb l) { return l == Limb::LeftArm || l == Limb::RightArm; }
inline bool isLeg(Limb l) { return l == Limb::LeftLeg || l == Limb::RightLeg; }

struct LimbPlace {
  Limb limb = Limb::Torso;
  double distance = 0;  // m from the point to the limb's axis
  double t = 0;         // fraction of the axis length from its root (shoulder, hip, pelvis, neck)
};

class BodyFrame {
 public:
  // canonical: kNumCanonical×3, the posed body's canonical points (same frame as the garments).
  // Throws InputError for a wrong shape or non-finite points.
  explicit BodyFrame(const Eigen::MatrixX3d& canonical);

  Eigen::Vector3d at(Canonical c) const { return canonical_.row(static_cast<int>(c)).transpose(); }
  const Eigen::Vector3d& up() const { return up_; }        // pelvis → neck
  const Eigen::Vector3d& left() const { return left_; }    // right hip → left hip, ⟂ up
  const Eigen::Vector3d& front() const { return front_; }  // left × up
  double height(const Eigen::Vector3d& p) const { return (p - at(Canonical::Pelvis)).dot(up_); }
  double lateral(const Eigen::Vector3d& p) const { return (p - at(Canonical::Pelvis)).dot(left_); }
  double frontal(const Eigen::Vector3d& p) const { return (p - at(Canonical::Pelvis)).dot(front_); }
  // The limb axis closest to p (torso: pelvis → neck; neck: neck → head; arms: shoulder →
  // elbow → wrist; legs: hip → knee → ankle).
  LimbPlace nearestLimb(const Eigen::Vector3d& p) const;
  // Where p lies along one limb's axis.
  LimbPlace placeOn(Limb limb, const Eigen::Vector3d& p) const;
  // "left" or "right": the side of the sagittal plane p lies on.
  const char* side(const Eigen::Vector3d& p) const { return lateral(p) >= 0 ? "left" : "right"; }

 private:
  Eigen::MatrixX3d canonical_;
  Eigen::Vector3d up_, left_, front_;
};

// The height (along the body's up axis from the pelvis, m) of the armpit on one side of a closed
// body mesh: the highest level at which a horizontal ray outwards in the shoulder's coronal
// plane leaves the torso and then crosses the arm (below it arm and torso are apart). NaN when
// no level below the shoulder does.
double armpitHeight(const TriMesh& body, const BodyFrame& frame, bool left);

// Which limb each vertex of the model belongs to, by its skinning weights: #V×6, column
// static_cast<int>(Limb), the vertex's weights summed over the limb's joints (an arm: its shoulder
// joint and every joint below it; a leg: its hip and below; the neck: the neck and below; the
// torso: every other joint). Rows sum to 1. Posing keeps the weights, so the rows hold for the
// posed and the fully fitted body alike (same vertices).
Eigen::MatrixXd limbWeights(const BodyModel& model);

}  // namespace s2p
