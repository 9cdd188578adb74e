// Scanner-like corruptions of a synthetic scan: decimation (meshoptimizer, vertices stay on the
// surface), noise along the normal and holes where scanners miss (armpits, crotch, soles,
// crown).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

// Simplifies `mesh` to about targetVertices (meshopt_simplify: every kept vertex is an input
// vertex). Returns the input index of every output vertex (#V_out). Throws InputError when
// targetVertices < 100.
Eigen::VectorXi decimateMesh(TriMesh& mesh, int targetVertices);

// Moves every vertex along its normal by N(0, σ²), seeded. σ in metres, in [0, 0.05].
void addNormalNoise(TriMesh& mesh, double sigma, std::uint64_t seed);

struct HoleCut {
  Eigen::VectorXi keptFaces;     // #F_out: input face of every output face
  Eigen::VectorXi keptVertices;  // #V_out: input vertex of every output vertex
  int holes = 0;                 // holes cut (new boundary loops)
};

// Removes a disc of faces (those reachable from the vertex nearest to each centre through faces
// within `radius` of it) around each of `centres` (posed frame, in priority order). Shrinks a
// disc that would not give exactly one new boundary loop. The mesh must be closed.
HoleCut cutHoles(TriMesh& mesh, const std::vector<Eigen::Vector3d>& centres, double radius);

}  // namespace s2p
