// How far apart two surfaces are: closest-point distances both ways (the draped garment
// against the scanned one), as figures in millimetres and per vertex for colouring.
#pragma once

#include <Eigen/Core>

#include "core/tri_mesh.h"

namespace s2p {

// Distances from the vertices of one mesh to the surface of the other, area-weighted (each
// vertex carries a third of its faces' area, so the figures do not depend on the meshing).
struct SurfaceDistanceStats {
  double meanMm = 0;
  double p95Mm = 0;  // area-weighted 95th percentile
  double maxMm = 0;
  int argmax = -1;                                  // vertex where the distance is largest
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();  // its position, metres
};

struct MeshComparison {
  SurfaceDistanceStats aToB;  // vertices of A to the surface of B
  SurfaceDistanceStats bToA;  // vertices of B to the surface of A
  Eigen::VectorXd distanceA;  // #V_A, metres: each vertex of A to B (for colouring A)
  Eigen::VectorXd distanceB;  // #V_B, metres
  // max(aToB.meanMm, bToA.meanMm) etc.: the symmetric (Hausdorff-like) figures.
  double meanMm() const;
  double p95Mm() const;
  double maxMm() const;
};

// Closest points by the Embree BVH (core/mesh_query.h). Throws InputError for an empty or
// invalid mesh.
MeshComparison compareMeshes(const TriMesh& a, const TriMesh& b);

// Area-weighted statistics of per-vertex distances (metres) on `mesh`; #V distances.
SurfaceDistanceStats distanceStats(const TriMesh& mesh, const Eigen::VectorXd& distance);

// How far (mm) the top of `draped` hangs below the top of `scanned` along the unit vector `up`:
// the difference of their area-weighted 98th-percentile heights (negative: it rides higher). A
// garment held where it was scanned (by the shoulders, by the waist) gives a few mm; one that
// nothing holds there (a top wider than the chest with no straps, straps the scan did not join
// to the front, a waist looser than the body) slides down by tens of mm. Throws InputError for
// an empty or invalid mesh.
double topDropMm(const TriMesh& draped, const TriMesh& scanned, const Eigen::Vector3d& up);

}  // namespace s2p
