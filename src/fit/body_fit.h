// Shape and pose of the body under clothing (paper §4, App. A): staged Levenberg-Marquardt
// (Ceres) on the energy of fit_energy.h, translation → shape → joint rotations, repeated,
// with closest points and inside/outside re-found between stages (research note E §3).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "body/body_model.h"
#include "body/posing.h"
#include "core/tri_mesh.h"
#include "fit/fit_energy.h"

namespace s2p {

struct BodyFitInput {
  TriMesh scan;                       // metres, +Y up, facing +Z (see orientation.h)
  const BodyModel* model = nullptr;   // must outlive the call
  std::optional<BodyParams> initial;  // e.g. from keypoints; absent: initialisePose (pose_init.h)
};

struct BodyFitOptions {
  int cycles = 3;            // translation → shape → pose cycles (BSE: 3)
  int icpStepsPerStage = 1;  // inside/outside re-decided this many times per stage
  // Then ICP steps with β, θ and t all free: converges the coupled parameters (our addition).
  int finalSteps = 2;
  int maxIterations = 25;  // LM iterations per ICP step (BSE: 500; its solves stop after 11–24)
  // Relative cost change ending a solve (BSE: Ceres' default 1e-6).
  double functionTolerance = 1e-5;
  bool fitShape = true;  // false keeps β at its initial value
  // Metres: outside vertices farther than this are ignored in the shape stage (BSE).
  double shapePruneOutside = 0.05;
  // Data terms on about this many evenly spread body vertices (0: all of them).
  int maxFitVertices = 2000;
  FitWeights weights;
  int threads = 2;
};

struct FitStageReport {
  std::string name;  // "translation", "shape", "pose", "all" (the final joint refinement)
  int cycle = 0;
  double seconds = 0;
  int iterations = 0;                    // LM iterations over the stage's ICP steps
  double costBefore = 0, costAfter = 0;  // Ceres cost ½Σr², first and last ICP step
};

struct BodyFitResult {
  BodyParams params;                   // fitted β, θ, t
  PosedBody body;                      // the posed, shaped body
  std::vector<FitStageReport> stages;  // in order
  FitEnergyTerms energy;               // at the end, with the last correspondences
  double insideOrNear = 0;             // fraction of body vertices inside the scan or within 5 mm
  double seconds = 0;  // total, including the scan's spatial index and pose initialisation
  std::vector<std::string> warnings;  // e.g. pose initialisation failed and the rest pose was used
  double secondsByStage(const std::string& name) const;
};

// Throws InputError for a missing model, an invalid or tiny scan or initial parameters that do
// not fit the model; SolverError if Ceres reports a failure.
BodyFitResult runBodyFit(const BodyFitInput& input, const BodyFitOptions& options = {});

// Fraction of the vertices of `body` inside the scan (winding number > 0.5) or within
// `tolerance` metres of it.
double insideOrNearFraction(const ScanTarget& scan, const TriMesh& body, double tolerance = 0.005);

}  // namespace s2p
