// Per-face grain frames of a 3D panel and the Jacobians of a flattening in them: the common
// ground of the warp/weft refinement (flatten.h) and the strain metrics (flatten_metrics.h).
//
// Woven fabric has two thread directions: the warp (along the grain, the panel's vertical) and
// the weft (across it). On each face the warp is the grain projected into the face plane, the
// weft is n × warp, so (warp, weft, n) is right-handed and, seen from outside, the weft lies 90°
// counter-clockwise of the warp.
#pragma once

#include <Eigen/Core>

#include "core/tri_mesh.h"

namespace s2p {

struct GrainFrames {
  Eigen::MatrixX3d warp;  // #F×3 unit vectors: the grain projected into each face
  Eigen::MatrixX3d weft;  // #F×3 unit vectors: n × warp
  // #F×6 gradients of the three hat functions in the (warp, weft) frame, (gx0, gy0, gx1, gy1,
  // gx2, gy2) for corners 0, 1, 2 (1/m); zero rows for degenerate faces.
  Eigen::MatrixXd gradients;
  Eigen::VectorXd area;  // #F, m²
};

// Frames of every face. grain: the 3D grain direction (need not be unit, must be non-zero and
// finite). A face whose normal is parallel to the grain (|projected grain| < 1e-9) takes its
// first edge F(f,0)→F(f,1) as warp. Throws InputError for a zero or non-finite grain.
GrainFrames grainFrames(const TriMesh& panel, const Eigen::Vector3d& grain);

// #F×4 Jacobians of the flattening uv (#V×2) in each face's grain frame, column-major
// (J00, J10, J01, J11): column 0 (J00, J10) is the 2D image of a unit warp step, column 1 the
// image of a unit weft step.
Eigen::MatrixX4d grainJacobians(const GrainFrames& frames, const Eigen::MatrixX3i& F,
                                const Eigen::MatrixX2d& uv);

}  // namespace s2p
