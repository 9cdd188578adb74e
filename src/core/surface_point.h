// A point on a triangle mesh: a face and barycentric weights of its three corners.
#pragma once

#include <Eigen/Core>

#include "core/mesh_topology.h"
#include "core/tri_mesh.h"

namespace s2p {

struct SurfacePoint {
  int face = -1;                                   // index into F
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();  // weights of F(face, 0..2), summing to 1

  // The point at vertex v: the first face incident to v with weight 1 on v's corner.
  // Throws InputError when v is out of range or referenced by no face.
  static SurfacePoint atVertex(const MeshTopology& topology, const Eigen::MatrixX3i& F, int v);
  // Same without a topology: scans F (O(#F)).
  static SurfacePoint atVertex(const Eigen::MatrixX3i& F, int v);

  // 3D position Σ bary_k · V(F(face,k)). Throws InputError when face is out of range.
  Eigen::Vector3d position(const TriMesh& mesh) const;
  // Linear interpolation of a per-vertex field (#V×k) → 1×k.
  Eigen::RowVectorXd interpolate(const Eigen::MatrixX3i& F, const Eigen::MatrixXd& field) const;
  // Linear interpolation of a per-vertex scalar (#V).
  double interpolate(const Eigen::MatrixX3i& F, const Eigen::VectorXd& field) const;
  // Index of the corner whose weight is (numerically) 1, or -1 when not at a vertex.
  int vertexCorner(double tol = 1e-12) const;
};

// Barycentric coordinates (of a, b, c) of p's orthogonal projection onto the plane of the
// triangle; may be negative when the projection falls outside. Degenerate triangles fall
// back to closestPointBarycentric.
Eigen::Vector3d planeBarycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Barycentric coordinates of the point of triangle abc closest to p (all weights in [0, 1]):
// p projected into the face, clamped to its edges and corners. Robust to degenerate triangles.
Eigen::Vector3d closestPointBarycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                        const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// The surface point of `face` closest to p. Throws InputError when face is out of range.
SurfacePoint projectToFace(const TriMesh& mesh, int face, const Eigen::Vector3d& p);

}  // namespace s2p
