// The initial boundary curve on the scan (§5.1.2): a smooth curve through the projected anchor
// points, not the jagged chain of projected spline points.
//
// Method: weighted averages on surfaces (Panozzo et al. 2013, the paper's [PBDSH13]) with the
// scan's own embedding R³. Each curve point is an affine combination of the anchors (the
// centripetal Catmull-Rom weights, so the curve passes through every anchor without loops or
// cusps), computed in R³ and then projected to the closest scan point. Panozzo et al. use a
// higher-dimensional embedding so that averages of far-apart points stay near the surface; our
// anchors are 5–10 cm apart on limb and torso loops whose radius of curvature is larger than
// that, so the R³ average lies within millimetres of the surface and the closest point is the
// right one. Geodesic paths between anchors were not chosen: they are exact but kink at every
// anchor and need a smoothing pass of their own.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/mesh_query.h"
#include "core/surface_point.h"

namespace s2p {

// Samples a centripetal Catmull-Rom spline through `anchors` (#A×3, in order; closed or open)
// about every `spacing` metres and projects each sample to its closest point on the mesh of
// `query`. Anchors closer than 1e-9 m to their predecessor are merged. Throws InputError for
// spacing ≤ 0, non-finite anchors, or fewer than 3 distinct anchors on a closed curve (2 on an
// open one).
std::vector<SurfacePoint> surfaceSpline(const MeshQuery& query, const Eigen::MatrixX3d& anchors,
                                        bool closed, double spacing);

// The curve's points in R³ before projection (for tests and previews): samples of the same
// spline.
Eigen::MatrixX3d catmullRomSamples(const Eigen::MatrixX3d& anchors, bool closed, double spacing);

}  // namespace s2p
