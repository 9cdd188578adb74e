// Body measurements as a tailor takes them, read off a body mesh in its upright rest pose,
// and the inverse: shape parameters of any BodyModel fitted to a set of measurements.
//
// Frame of body_model.h: metres, +Y up, facing +Z, the body's left on +X; the body stands
// upright with its arms away from the torso (A-pose or T-pose). Every offset below is a
// fraction of the body height H so the definitions do not depend on scale or mesh
// resolution. Girths are tape measurements: the perimeter of the convex hull of one closed
// loop of a plane section (body/plane_section.h), the loop that winds around the part's
// axis point (the outermost such loop); loops of other parts cut by the same plane are
// ignored, and a torso loop that also winds around an arm bone (arm pressed to the side) is
// rejected at that height.
//
//   height           top of the head to the floor: max y − min y of the mesh.
//   crotch           highest height at which the left and right legs' bone points (on
//                    hip→knee) lie in different section loops (bisection to 0.1 mm).
//   inseam           crotch height − min y (inside leg to the floor, barefoot).
//   armpit           highest height below the shoulders at which the torso loop no longer
//                    winds around an arm bone.
//   chest_girth      fullest torso girth (horizontal) between the chest joint − 0.05 H and the
//                    armpit: the bust for a woman, the chest under the arms for a man.
//   under_bust_girth narrowest torso girth 0.02 H – 0.06 H (3.5 – 10 cm) below the bust line.
//   hip_girth        fullest torso girth around the buttocks between the crotch + 0.01 H and
//                    the hip joints' height + 0.02 H (at least crotch + 0.05 H).
//   waist_girth      natural waist: narrowest torso girth between the hip line + 0.02 H and
//                    the under-bust line.
//   neck_girth       plane ⟂ the neck bone (neck→head joints) at 35 % of its length from the
//                    neck joint (moved up in 5 % steps, to 60 %, while the loop still takes in
//                    a shoulder joint): the loop around the neck, as a collar is measured.
//   thigh_girth      horizontal plane 0.03 H (≈ 5 cm) below the crotch, loop around each
//                    thigh; the larger of left and right.
//   upper_arm_girth  planes ⟂ the upper-arm bone (shoulder→elbow) at 40–60 % of its length:
//                    the fullest loop around the arm (biceps), planes whose loop takes in a
//                    spine joint (arm against the torso) skipped; the larger of left and right.
//   shoulder_width   straight (caliper) distance between the left and right shoulder points,
//                    each the surface point straight above its shoulder joint (acromion); a
//                    tape laid across the back reads ~1–2 cm more.
//   arm_length       shoulder point → elbow joint → wrist joint along the bones (the tape over
//                    the bent elbow); the mean of left and right.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "body/body_model.h"
#include "core/tri_mesh.h"

namespace s2p {

// === Measurements

// Metres; NaN where not measured (not requested, or absent from a partial JSON).
struct BodyMeasurements {
  double height = kNotMeasured;
  double neckGirth = kNotMeasured;
  double chestGirth = kNotMeasured;
  double underBustGirth = kNotMeasured;
  double waistGirth = kNotMeasured;
  double hipGirth = kNotMeasured;
  double thighGirth = kNotMeasured;
  double upperArmGirth = kNotMeasured;
  double shoulderWidth = kNotMeasured;
  double armLength = kNotMeasured;
  double inseam = kNotMeasured;

  static constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();
};

// The snake_case names used in JSON and targets: "height", "neck_girth", "chest_girth",
// "under_bust_girth", "waist_girth", "hip_girth", "thigh_girth", "upper_arm_girth",
// "shoulder_width", "arm_length", "inseam".
const std::vector<std::string>& measurementNames();
// The field called `name`; throws InputError listing the valid names when unknown.
double& measurementField(BodyMeasurements& m, std::string_view name);
double measurementField(const BodyMeasurements& m, std::string_view name);

struct MeasureOptions {
  std::vector<std::string> only;  // names to measure; empty = all (others stay NaN)
};

// Measures a body mesh (upright, see the definitions above). `canonical` is
// kNumCanonical×3, rows indexed by Canonical (PosedBody::canonical of posing.h). Throws
// InputError on an invalid mesh or canonical matrix, an unknown name in `only`, or when a
// measurement cannot be taken (e.g. legs not apart, torso not found at the chest).
BodyMeasurements measureBody(const TriMesh& mesh, const Eigen::MatrixX3d& canonical,
                             const MeasureOptions& options = {});

// {"units": "m", "height": 1.72, ..., "cm": {"height": 172.0, ...}}: metres at the top level
// (measured values only), the same in centimetres (rounded to 0.1 mm) under "cm" for people.
nlohmann::json toJson(const BodyMeasurements& m);
// Reads the top-level metres (a partial set is fine: the rest stays NaN); "units" must be
// "m" when present and "cm" is ignored. Throws InputError on a non-object, an unknown name,
// or a value that is not a positive finite number.
BodyMeasurements measurementsFromJson(const nlohmann::json& json);

// === Fitting shape to measurements

// Requested measurements: name (as in measurementNames()) → metres.
struct MeasurementTargets {
  std::map<std::string, double> values;
};
// The measured (non-NaN) values of `m` as targets.
MeasurementTargets toTargets(const BodyMeasurements& m);

struct MeasurementFitOptions {
  int maxIterations = 30;        // Levenberg–Marquardt iterations
  double tolerance = 1e-4;       // metres: stop when every measurement is this close
  double regularization = 1e-8;  // m² per unit² of β: keeps undetermined parameters near 0
  double step = 0.05;            // finite-difference step in β units (central differences)
  Eigen::VectorXd initial;       // start (#S); empty = zeros
};

// Measures the model's rest-pose body (θ = 0, no translation) at shape β (#S).
BodyMeasurements measureRestBody(const BodyModel& model, const Eigen::VectorXd& shape,
                                 const MeasureOptions& options = {});

// Shape parameters β (#S, within each ShapeParam's [min, max]) whose rest-pose measurements
// match the targets in the least-squares sense (Levenberg–Marquardt on finite differences).
// Throws InputError on an unknown or non-positive target, no targets, a model without shape
// parameters or with inconsistent sizes.
Eigen::VectorXd fitShapeToMeasurements(const BodyModel& model, const MeasurementTargets& targets,
                                       const MeasurementFitOptions& options = {});

}  // namespace s2p
