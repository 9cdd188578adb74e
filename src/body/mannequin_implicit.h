// The mannequin as a smooth implicit function: lofted elliptical sections along bones
// (torso, neck, limbs, hands, feet) and ellipsoids (head, jaw, nose, deltoids), blended with a
// polynomial smooth minimum. Every dimension derives from tailor measurements; the girths,
// height and inseam are calibrated numerically so that a tape on the implicit surface reads
// the requested values. Used by makeMannequin (mannequin.h) to mesh the template and to
// compute the shape blend shapes.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace s2p {

// Tailor measurements of the mannequin, metres. Where each is taken (the definitions the
// calibration and the tests use):
struct MannequinMeasurements {
  double height = 1.75;     // floor to head top
  double chest = 0.96;      // horizontal torso girth at chestLevel (convex hull, as a tape)
  double waist = 0.82;      // horizontal torso girth at waistLevel
  double hip = 0.98;        // horizontal torso girth at hipLevel (fullest buttocks)
  double shoulder = 0.36;   // distance between the two shoulder joints (glenohumeral centres)
  double armLength = 0.56;  // shoulder joint → elbow joint → wrist joint (straight arm)
  double inseam = 0.80;     // floor to crotch
  double neck = 0.38;       // neck girth ⟂ the neck axis, 40% from neck joint to head joint
  double thigh = 0.56;      // horizontal girth of one thigh 5 cm (×height/1.75) below the crotch
  double upperArm = 0.31;   // girth perpendicular to the upper arm at mid shoulder–elbow
};

// Heights (y, metres) of the horizontal tape planes of the chest, waist and hip girths.
struct MannequinLevels {
  double chest = 0, waist = 0, hip = 0;
};
MannequinLevels mannequinLevels(const MannequinMeasurements& m);

// Skeleton joints of the mannequin, parents before children; the first 19 follow
// Canonical's order (pelvis … right_ankle).
enum MannequinJoint : int {
  kMjPelvis,
  kMjSpine,
  kMjChest,
  kMjNeck,
  kMjHead,
  kMjLeftClavicle,
  kMjRightClavicle,
  kMjLeftShoulder,
  kMjRightShoulder,
  kMjLeftElbow,
  kMjRightElbow,
  kMjLeftWrist,
  kMjRightWrist,
  kMjLeftHip,
  kMjRightHip,
  kMjLeftKnee,
  kMjRightKnee,
  kMjLeftAnkle,
  kMjRightAnkle,
  kMjLeftToe,
  kMjRightToe,
  kMjLeftHand,
  kMjRightHand,
  kMjCount
};
const std::array<int, kMjCount>& mannequinParents();
const std::array<const char*, kMjCount>& mannequinJointNames();

// A loft: elliptical sections swept along a straight axis, with ellipsoidal end caps.
// An ellipsoid is a loft of length 0 with one section and caps equal to its third radius.
struct Loft {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // axis start
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();   // unit axis direction
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();      // section frame, unit, ⟂ axis
  Eigen::Vector3d v = Eigen::Vector3d::UnitZ();      // unit, ⟂ axis and u
  double length = 0;                                 // metres
  std::vector<double> t;                             // knots in [0, 1], increasing
  std::vector<Eigen::Vector4d> sec;                  // per knot: (a along u, b along v, cu, cv)
  double capStart = 0.01, capEnd = 0.01;             // ellipsoidal cap lengths, metres
  double blend = 0.03;                               // smooth-min radius when merged, metres
  std::vector<std::pair<double, int>> bones;         // (local axial coord, joint): skinning
  Eigen::Vector4d section(double tt) const;          // PCHIP-interpolated section at tt ∈ [0,1]
  void finalize();                                   // slopes and bound radius, after knots set
  // Axial fraction tt ↔ knot space (knot i at i/(#knots−1), linear between knots): vertices
  // keep their place between the same two sections when the sections move.
  double knotSpace(double tt) const;
  double fromKnotSpace(double w) const;
  std::vector<Eigen::Vector4d> slope;  // PCHIP derivative per knot
  double boundRadius = 0;              // max section extent from the axis
};

// Position of a point relative to one loft: axial coordinate (knot space in [0,1] along the
// axis, < 0 or > 1 in the caps, in units of cap length beyond the end) and section-normalised
// (ξ, η).
struct LoftCoords {
  double axial = 0, xi = 0, eta = 0;
};

class MannequinImplicit {
 public:
  // Throws InputError for implausible measurements. `warmStart`: a nearby body whose
  // calibration starts this one's (faster, same result).
  explicit MannequinImplicit(const MannequinMeasurements& m,
                             const MannequinImplicit* warmStart = nullptr);

  double value(const Eigen::Vector3d& p) const;  // < 0 inside, ≈ signed distance near 0
  Eigen::Vector3d gradient(const Eigen::Vector3d& p) const;  // central differences
  // Newton steps along the gradient onto the zero level set.
  Eigen::Vector3d project(const Eigen::Vector3d& p, int iterations = 4) const;

  int numPrimitives() const { return static_cast<int>(prims_.size()); }
  const Loft& primitive(int k) const { return prims_[k]; }
  // Lower bound of every primitive's field at p (for culling far-away space).
  double lowerBound(const Eigen::Vector3d& p) const;
  // Raw field of primitive k at p (no blending).
  double primitiveValue(int k, const Eigen::Vector3d& p) const;
  LoftCoords coords(int k, const Eigen::Vector3d& p) const;
  Eigen::Vector3d position(int k, const LoftCoords& c) const;

  const Eigen::Matrix<double, kMjCount, 3>& joints() const { return joints_; }  // #J×3
  const MannequinMeasurements& measurements() const { return m_; }
  // Lower/upper corners of a box containing the body.
  Eigen::Vector3d boxMin() const;
  Eigen::Vector3d boxMax() const;

  // === What a tape reads on the implicit surface (used by the calibration).
  // Convex hull perimeter of the section through `centre` ⟂ `normal`, star-shaped from centre.
  double sectionGirth(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal) const;
  double headTop() const;  // max y on the head
  double crotch() const;   // lowest torso point between the legs
  Eigen::Vector3d thighTapeCentre(bool left) const;
  Eigen::Vector3d upperArmTapeCentre(bool left, Eigen::Vector3d* normal) const;
  Eigen::Vector3d neckTapeCentre(Eigen::Vector3d* normal) const;

 private:
  struct Knobs {
    double headShift = 0, crotchShift = 0;
    double chest = 1, waist = 1, hip = 1, neck = 1, thigh = 1, upperArm = 1;
  };
  void build(const Knobs& k);
  double chainValue(int begin, int end, const Eigen::Vector3d& p, double cutoff) const;
  double bound(int k, const Eigen::Vector3d& p) const;

  MannequinMeasurements m_;
  std::vector<Loft> prims_;
  std::vector<std::pair<int, int>> limbs_;  // primitive ranges [begin, end) of each limb chain
  int coreEnd_ = 0;                         // primitives [0, coreEnd_) form the core chain
  std::vector<double> limbBlend_;
  Eigen::Matrix<double, kMjCount, 3> joints_;
  double crotchZ_ = 0;
  Knobs knobs_;
};

}  // namespace s2p
