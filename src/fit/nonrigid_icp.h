// Optimal-step non-rigid ICP (Amberg, Romdhani & Vetter, CVPR 2007): a per-vertex affine
// transform X_i (4×3) of a template, minimising
//   E = Σ w_i |X_iᵀ ṽ_i − u_i|² + α² Σ_edges |(X_i − X_j)ᵀ G|² + β² Σ_landmarks |X_lᵀ ṽ_l − l|²
// (ṽ = (v, 1), G = diag(1, 1, 1, γ), u_i the closest target point), one sparse linear solve
// per correspondence update, with the stiffness α decreasing from stiff to soft. Used to bring
// the fitted body onto the scan surface so feature points can be carried (paper §5.1.2).
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

struct NonrigidIcpOptions {
  // Stiffness α and landmark weight β per outer step, in the frame scaled to a unit bounding-box
  // diagonal (menpo3d's schedule, research note E §7).
  std::vector<double> stiffness = {50, 20, 5, 2, 0.8, 0.5, 0.35, 0.2};
  std::vector<double> landmarkWeight = {5, 2, 0.5, 0, 0, 0, 0, 0};
  double gamma = 1;           // weight of the translation column in the stiffness term
  double maxDistance = 0.10;  // metres: farther correspondences get w = 0
  double minNormalDot = 0.5;  // correspondences with n_template·n_target below get w = 0
  int maxInnerIterations = 10;
  double tolerance = 1e-4;  // RMS change of X per entry (unit-diagonal frame) ending a step
  // The data weights (distance and normal tests) decided once per stiffness step, at its first
  // correspondence update; later updates move only the closest points, so the step's system
  // matrix is factored once. false: re-decided at every update (Amberg et al.; one factorisation
  // per solve, ≈ 6× slower on a 15k-vertex body).
  bool weightsPerStep = true;
};

struct NonrigidIcpResult {
  TriMesh mesh;             // the template deformed onto the target (faces of the template)
  int iterations = 0;       // linear solves in total
  int factorisations = 0;   // numeric factorisations (a solve reuses the last when A is unchanged)
  double meanDistance = 0;  // metres, template vertices to the target at the end
};

// Throws InputError for empty or invalid meshes, a schedule with different lengths or a
// landmark index out of range; SolverError if a system cannot be factored.
NonrigidIcpResult runNonrigidIcp(const TriMesh& templ, const TriMesh& target,
                                 const std::vector<std::pair<int, Eigen::Vector3d>>& landmarks = {},
                                 const NonrigidIcpOptions& options = {});

}  // namespace s2p
