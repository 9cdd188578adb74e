// Boundary metrics (issue 4 "Metrics"): distance between predicted and true boundary curves,
// sampled at uniform arc length, and roughness = predicted length / true length (jagged
// per-vertex boundaries score high: the paper's argument against MRF labelling, §5).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "eval/labelling.h"
#include "synth/truth.h"

namespace s2p {

// Curves between faces of different labels on a labelled mesh, as chains of the mesh edges
// shared by a face of label a and a face of label b (a < b), one TrueBoundary per label pair
// present, sorted by (a, b). A chain ends where the boundary branches (a vertex with more than
// two such edges) or meets the mesh boundary; closed loops come out closed. With skipGap, as in
// truth.json, a garment's edge with gap-filling faces (the rim of a hanging hem) counts as its
// boundary with the skin and every other gap edge is left out.
std::vector<TrueBoundary> extractLabelBoundaries(const LabelledMesh& m, bool skipGap = true);

// Points at uniform arc length along a polyline (closed: including the closing segment), the
// spacing at most maxSpacing (metres), both ends included on an open curve. #S×3.
Eigen::MatrixX3d samplePolyline(const Eigen::MatrixX3d& curve, bool closed, double maxSpacing);

// Distance from every row of P to the nearest point of any of the curves' segments. #P.
Eigen::VectorXd distanceToCurves(const Eigen::MatrixX3d& P, const TrueBoundary& curves);

struct DistanceStats {
  int count = 0;
  double mean = 0;  // metres
  double p95 = 0;   // metres, 95th percentile (linear interpolation between order statistics)
  double max = 0;   // metres
};
DistanceStats distanceStats(const Eigen::VectorXd& d);

struct BoundaryScore {
  Label a = Label::Skin, b = Label::Skin;
  bool missing = true;       // no predicted curve for this pair: distances and roughness unset
  double trueLength = 0;     // m
  double predLength = 0;     // m
  double roughness = 0;      // predLength / trueLength
  DistanceStats predToTrue;  // predicted samples → true curves
  DistanceStats trueToPred;  // true samples → predicted curves
  DistanceStats pooled;      // both directions together
};

struct BoundaryMetricOptions {
  double sampleSpacing = 0.5e-3;  // m, arc-length spacing of the samples (≤ 1 mm)
};

// Compares the predicted curves of one label pair with the true ones. pred == nullptr or
// without points → missing.
BoundaryScore compareBoundary(const TrueBoundary& truth, const TrueBoundary* pred,
                              const BoundaryMetricOptions& options = {});

}  // namespace s2p
