// The body-under-clothing energy of the paper's App. A (Eq. 7–10) as one residual vector with
// an analytic Jacobian, for a Levenberg-Marquardt solver:
//   E = λ_out Σ_{i outside} |v_i − c_i|² + λ_in Σ_{i inside} GM(|v_i − c_i|²)
//     + λ_β |β·rms_β / ρ|² + λ_θ |θ − θ_init|² + λ_lim Σ (soft joint-limit excess)²
// with c_i the closest scan point of body vertex i, recomputed at every evaluation as in the
// paper's code; which term a vertex feeds (inside / outside / ignored) is decided once per ICP
// step (winding numbers are costlier), with the ICP heuristics of the paper's code (research note E
// §2): a vertex whose normal opposes the scan's (n_v·n_c ≤ 0) or that lies too far away is ignored.
// Derivatives come from the posing Jacobian (Poser::vertexJacobian), never numeric.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "body/posing.h"
#include "core/mesh_query.h"
#include "core/tri_mesh.h"

namespace s2p {

// === Correspondences (one ICP step)

enum class FitSide : signed char { Ignored = 0, Outside = 1, Inside = -1 };

struct Correspondences {
  Eigen::MatrixX3d closest;   // #V×3 closest scan point per body vertex
  Eigen::VectorXd distance;   // #V, metres
  std::vector<FitSide> side;  // #V: which term the vertex feeds
  Eigen::VectorXd winding;    // #V: winding number of the scan at the vertex (0 if not considered)
  std::vector<int> face;  // #V: scan face of the closest point (−1 if not considered), or empty
  int sampled = 0;        // vertices considered (all, or a subset); data terms scale by 1/sampled
  int numOutside() const;
  int numInside() const;
};

struct CorrespondenceOptions {
  // Metres: outside vertices farther than this are ignored (BSE: 0.05 in the shape stage).
  double pruneOutside = 1e9;
  double pruneInside = 1e9;  // metres: same for inside vertices (BSE: off)
  bool normalTest = true;    // ignore vertices whose normal opposes the scan's: n_v·n_c ≤ 0
};

// The scan with what the correspondences need, built once per fit.
class ScanTarget {
 public:
  explicit ScanTarget(const TriMesh& scan);
  const MeshQuery& query() const { return query_; }
  const Eigen::MatrixX3d& faceNormals() const { return faceNormals_; }  // #F×3
  const TriMesh& mesh() const { return mesh_; }

 private:
  TriMesh mesh_;
  MeshQuery query_;
  Eigen::MatrixX3d faceNormals_;
};

// Closest point, inside / outside (winding number > 0.5: robust to holes) and the ICP
// heuristics for every vertex of `body`, or only for `subset` (the others are Ignored).
Correspondences findCorrespondences(const ScanTarget& scan, const TriMesh& body,
                                    const CorrespondenceOptions& options = {},
                                    const std::vector<int>* subset = nullptr);

// === Energy

struct FitWeights {
  double out = 1.0;  // λ_out (BSE)
  double in = 0.1;   // λ_in (BSE in_verts_scaling_weight)
  // Metres: Geman-McClure scale, GM(s) = s·σ²/(σ² + s). BSE uses 2 m, quadratic in effect; 5 cm
  // makes loose clothing far from the body pull less.
  double gmSigma = 0.05;
  // λ_β (BSE) on β_s·rms_s/shapeRms, rms_s the RMS vertex displacement of a unit β_s, so the
  // prior means the same for every body source whatever the units of its parameters.
  double shape = 0.01;
  double shapeRms = 0.02;  // metres: RMS displacement counted as one unit of shape
  // λ_θ with identity covariance about θ_init, root excluded. BSE: 0.001·√Σ⁻¹ of SMPLify's
  // pose GMM, which exists for SMPL only.
  double pose = 0.01;
  double limits = 10.0;  // λ_lim on the excess over a joint's limits, radians
  // Data terms scaled by this / #sampled vertices: BSE's balance (6890 SMPL vertices) with
  // priors at any template size.
  double referenceVertices = 6890;
};

// Per joint, bounds on the three axis-angle components (radians), soft (penalised) limits.
struct JointLimits {
  Eigen::MatrixX3d lower, upper;  // #J×3
};
// Knees bend one way only, the spine, neck and head turn little, every other joint within
// ±0.9π per component; the root is free.
JointLimits defaultJointLimits(const BodyModel& model);

// Energy terms E_x = Σ r² of their residuals (no ½).
struct FitEnergyTerms {
  double out = 0, in = 0, shape = 0, pose = 0, limits = 0;
  double total() const { return out + in + shape + pose + limits; }
};

class FitEnergy {
 public:
  // `poser` and `scan` must outlive this; `initial` is θ_init of the pose prior.
  FitEnergy(const Poser& poser, const ScanTarget& scan, const BodyParams& initial,
            const FitWeights& weights, JointLimits limits);

  void setCorrespondences(Correspondences c);
  const Correspondences& correspondences() const { return corr_; }
  // Residuals: [1 per body vertex: √λ·|d| or √(λ·GM(|d|²)), zero when ignored | #S shape |
  // 3(#J−1) pose | 3(#J−1) limits].
  int numResiduals() const;
  int numParams() const { return poser_.numParams(); }  // P = #S + 3#J + 3
  // r (numResiduals) and, when J is given, ∂r/∂params (numResiduals × P, order [β | θ | t]).
  // `needShapeAndPose` false leaves the β and θ columns zero (the translation stage).
  void evaluate(const BodyParams& params, Eigen::VectorXd* r, Eigen::MatrixXd* J,
                bool needShapeAndPose = true) const;
  // The same residuals without the always-zero rows of ignored vertices: [one per active vertex,
  // in vertex order | #S shape | 3(#J−1) pose | 3(#J−1) limits]; what a solver should see
  // (a 2000-vertex sample of a 15k-vertex body: 7× fewer Jacobian rows).
  int numCompactResiduals() const;
  void evaluateCompact(const BodyParams& params, Eigen::VectorXd* r, Eigen::MatrixXd* J,
                       bool needShapeAndPose = true) const;
  FitEnergyTerms terms(const BodyParams& params) const;

 private:
  const Poser& poser_;
  const ScanTarget& scan_;
  BodyParams initial_;
  FitWeights w_;
  JointLimits limits_;
  Correspondences corr_;
  Eigen::VectorXd shapeScale_;  // #S: rms_s / shapeRms
  // Rows of r: active vertex a on row a (compact) or on row active_[a], priors after them.
  void evaluateRows(const BodyParams& params, Eigen::VectorXd* r, Eigen::MatrixXd* J,
                    bool needShapeAndPose, bool compact) const;
  std::vector<int> active_;  // vertices not ignored
  // Closest points of the last evaluation point: Levenberg-Marquardt evaluates an accepted
  // point twice (cost, then Jacobian). Shared by copies; guarded by a mutex.
  struct HitCache;
  std::shared_ptr<HitCache> cache_;
};

// Packing of BodyParams into one vector [β | θ (joint-major) | t] and back.
Eigen::VectorXd packParams(const BodyParams& p);
BodyParams unpackParams(const BodyModel& model, const Eigen::VectorXd& x);

}  // namespace s2p
