// A decimated copy of a large scan on which the boundaries are optimised (issue 17, "Scale").
// Algorithm 1's cost grows faster than the vertex count (a fast-marching sweep over the whole
// mesh per iteration, sparse Cholesky factors of M + βL and of L M⁻¹ L whose fill grows as
// n log n and more), while the boundary it finds is set by lengths of millimetres to
// centimetres (α, √β, the colour smoothing) that about 100k vertices on a person resolve. The
// copy's vertices are a subset of the fine mesh's (meshoptimizer's edge collapses), so
// per-vertex data carry over by index; a field found on the copy is carried back to every fine
// vertex by interpolation at its closest point on the copy, and the scan is cut exactly along
// that field's zero isoline on the fine mesh.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "core/tri_mesh.h"

namespace s2p {

struct CoarseMesh {
  TriMesh mesh;
  Eigen::VectorXi fineVertex;  // #V of the copy: the fine vertex each one is
};

// A copy of `fine` with about `targetVertices` vertices; nullopt when `fine` has no more than
// 1.5 × targetVertices (the copy would not pay for itself) or when no copy was found without
// non-manifold edges, faces of inconsistent orientation or vertices without area that `fine`
// does not have (the caller then works on the fine mesh). Throws InputError for
// targetVertices < 1000.
std::optional<CoarseMesh> decimatedCopy(const TriMesh& fine, int targetVertices);

// Where each vertex of a fine mesh lies on a coarse copy of it (its closest point there):
// carries per-vertex fields from the copy to the fine mesh by barycentric interpolation.
class CoarseToFine {
 public:
  CoarseToFine(const TriMesh& coarse, const TriMesh& fine);
  // #V of the fine mesh from `coarseField` (#V of the copy).
  Eigen::VectorXd carry(const Eigen::VectorXd& coarseField) const;
  // Distance (m) from each fine vertex to the copy: how far the copy strays from the scan.
  const Eigen::VectorXd& distance() const { return distance_; }

 private:
  Eigen::MatrixX3i corner_;   // #V fine × 3: coarse vertices of the face holding the closest point
  Eigen::MatrixX3d weight_;   // #V fine × 3: their barycentric weights
  Eigen::VectorXd distance_;  // #V fine
};

}  // namespace s2p
