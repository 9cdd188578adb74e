// Point location in a flattened (uv) triangle mesh: which face of the flat panel a 2D point
// lies in and its barycentric weights, so that anything defined on the panel (its 3D shape,
// the scan's colours and texture coordinates) travels to a remeshed pattern.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/surface_point.h"
#include "core/tri_mesh.h"

namespace s2p {

class UvLocator {
 public:
  // uv: #V×2, F: #F×3 (orientation free; degenerate faces are skipped). A uniform grid of
  // about #F cells, each listing the faces whose bounding box meets it. Throws InputError for
  // an empty mesh, out-of-range indices or non-finite uv.
  UvLocator(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& F);

  // The face containing p and its barycentric weights (Σ = 1, all ≥ −1e-12); the face most
  // inside when p is on a shared edge. A point outside the mesh (e.g. a Bézier outline sample
  // up to its fit tolerance outside the flattened boundary) gets the closest point of the mesh,
  // weights in [0, 1]. distance: how far p is from the returned location (0 inside).
  SurfacePoint locate(const Eigen::Vector2d& p, double* distance = nullptr) const;
  // All rows of P (#P×2), in parallel. distances: #P, optional.
  std::vector<SurfacePoint> locate(const Eigen::MatrixX2d& P,
                                   Eigen::VectorXd* distances = nullptr) const;

  int numFaces() const { return static_cast<int>(F_.rows()); }

 private:
  Eigen::MatrixX2d uv_;
  Eigen::MatrixX3i F_;
  Eigen::Vector2d lo_;
  double cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<int> cellStart_, cellFaces_;  // CSR cell → faces
};

// Interpolation of a per-vertex field (#V×k) of the located mesh at the locations → #P×k
// (e.g. the 3D positions of the panel: the remeshed pattern's 3D shape).
Eigen::MatrixXd interpolateAt(const std::vector<SurfacePoint>& locations, const Eigen::MatrixX3i& F,
                              const Eigen::MatrixXd& field);

}  // namespace s2p
