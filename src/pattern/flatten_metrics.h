// Quality figures of a flattening (issue 15's per-panel report): area distortion, warp/weft
// strain as pattern software measures it (parafashion's s_u, s_v; ±5 % is the usual bound),
// boundary length error, inverted faces and boundary self-intersection.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

// Area-weighted quantiles of a per-face quantity (the face's 3D area is its weight).
struct StrainSummary {
  double median = 0.0;
  double p95 = 0.0;
  double max = 0.0;
};

struct FlatteningMetrics {
  double area3d = 0.0;              // m²
  double area2d = 0.0;              // m², Σ of signed face areas in uv
  double areaDistortionMean = 0.0;  // area-weighted mean over faces of |log(A2D/A3D)|
  double areaDistortionMax = 0.0;   // max over faces of the same (∞ for an inverted face)
  StrainSummary warp;  // |ℓ − 1|, ℓ the 2D length of a unit 3D step along the grain
  StrainSummary weft;  // same across the grain (n × grain)
  double edgeLengthErrorMax = 0.0;      // max over edges of |ℓ2D/ℓ3D − 1|
  double boundaryLength3d = 0.0;        // m
  double boundaryLength2d = 0.0;        // m
  double boundaryLengthError = 0.0;     // |L2D − L3D| / L3D
  int invertedFaces = 0;                // faces with signed uv area ≤ 0
  bool boundarySelfIntersects = false;  // the uv boundary loop touches or crosses itself
};

// Figures of uv (#V×2) as a flattening of panel3d (a disk; its boundary loop is taken from the
// faces) with grain the 3D grain direction. Throws InputError when uv does not match the panel.
FlatteningMetrics flatteningMetrics(const TriMesh& panel3d, const Eigen::MatrixX2d& uv,
                                    const Eigen::Vector3d& grain);

// True when the closed polygon uv(loop[0]), uv(loop[1]), ... touches or crosses itself: two
// non-adjacent edges intersect, or two adjacent edges fold back onto each other. Exact
// orientation predicates (CGAL's Epick), a uniform grid over the edges: O(n) for a fair loop.
// With `crossings`, every offending pair of segments (segment i runs loop[i] → loop[i+1]) is
// collected, sorted and unique, instead of stopping at the first.
bool polygonSelfIntersects(const Eigen::MatrixX2d& uv, const std::vector<int>& loop,
                           std::vector<std::pair<int, int>>* crossings = nullptr);

}  // namespace s2p
