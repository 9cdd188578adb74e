// Remeshing of a flattened panel (paper §6.2: "we resample the points along the edge, and
// perform Delaunay triangulation using TRIANGLE"): a quality constrained Delaunay triangulation
// of the outline with CGAL's 2D mesher (Mesh_2, Ruppert/Shewchuk refinement; it replaces
// Triangle), every boundary sample kept as a vertex.
//
// The boundary is given as edges, each its own samples (the caller resamples each Bézier edge,
// giving two stitched edges the same count so that a simulator pairs them vertex to vertex).
// By default no Steiner point is put on the boundary: the refinement runs with CGAL's
// Delaunay_mesher_no_edge_refinement_2, which drops a refinement point that would encroach
// upon a boundary segment instead of splitting the segment. The angle bound is then reached
// wherever the boundary spacing allows it, and so is the size bound: sample each edge with
// boundarySampleCount points (spacing ≤ 0.7 × target; at spacing = target, triangles on the
// boundary keep edges up to ~1.17 × target, whose refinement points would encroach) and keep
// corner angles ≥ 2× the bound. A face the mesher leaves below the bound (its circumcentre
// encroaches: a short boundary segment beside long ones) is offered other interior points, the
// best kept (repairBadFaces in remesh.cpp). minAngleDeg, badFaces and longestEdge say whether
// the bound was reached. With
// allowBoundarySteiner the ordinary Delaunay_mesher_2 also splits boundary segments (the bound is
// then guaranteed for input angles ≥ 60°) and edgeVertices lists the inserted vertices too.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

struct RemeshOptions {
  double targetEdgeLength = 0.01;  // m: upper bound on every triangle edge (CGAL's size bound)
  // Minimum angle bound (degrees): CGAL's shape bound B = sin²(angle); 20.7° ↔ B = 0.125, the
  // largest bound with a termination guarantee, and the largest accepted.
  double minAngleDeg = 20.7;
  bool allowBoundarySteiner = false;  // let the mesher split boundary segments
  // Without boundary Steiner points, offer the faces CGAL leaves below the angle bound other
  // interior points (repairBadFaces). Costly on an outline of many short, uneven segments (a
  // scan's crease): a membrane that is only a surface to cut seams on does without it.
  bool repairBadFaces = true;
};

struct RemeshedPanel {
  Eigen::MatrixX2d V;  // #V×2, metres: the boundary vertices first (in outline order), then inside
  Eigen::MatrixX3i F;  // #F×3, counter-clockwise
  // Per input edge, the output vertex of each of its samples in order (first and last are the
  // corners it shares with its neighbours; with allowBoundarySteiner also inserted vertices).
  std::vector<std::vector<int>> edgeVertices;
  int numBoundaryVertices = 0;
  int boundarySteinerPoints = 0;  // vertices the mesher added on the boundary
  double minAngleDeg = 0.0;       // smallest angle of F
  int badFaces = 0;               // faces with an angle below options.minAngleDeg
  double area = 0.0;              // Σ face areas (m²)
  double longestEdge = 0.0;       // m

  // The 2D mesh as a TriMesh with z = 0.
  TriMesh toTriMesh() const;
};

// Remeshes the closed outline given by edges (each #Pk×2, Pk ≥ 2, in order around the panel:
// edge k's last sample equals edge k+1's first, the last edge's last the first edge's first;
// either orientation). name: the panel's name for error messages. Throws InputError when edges
// do not join up, samples repeat, the outline crosses itself or encloses no area, or an option
// is out of range.
RemeshedPanel remeshPanel(const std::vector<Eigen::MatrixX2d>& edges, const std::string& name,
                          const RemeshOptions& options = {});

// Samples (end points included) for an edge of the given length so that remeshPanel, without
// boundary Steiner points, meets the size bound: ⌈length / (0.7 · target)⌉ + 1 (at least 2).
// Give two stitched edges the count of their mean length so that they pair vertex to vertex.
int boundarySampleCount(double edgeLength, double targetEdgeLength);

// Smallest interior angle (degrees) of the 2D triangles (V #V×2, F #F×3); 0 for degenerate.
double minimumAngleDeg(const Eigen::MatrixX2d& V, const Eigen::MatrixX3i& F);

}  // namespace s2p
