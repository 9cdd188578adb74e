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
// vertex). meshopt_simplify does not check the link condition; the few non-manifold edges it can
// leave where two sheets come within an edge length are split apart (splitNonManifold), so the
// result is manifold. Returns the input index of every output vertex (#V_out). Throws InputError
// when targetVertices < 100.
Eigen::VectorXi decimateMesh(TriMesh& mesh, int targetVertices);

// Makes a mesh manifold without moving anything: around every vertex the faces connected through
// manifold edges (exactly two faces) form a fan, and every fan but the first gets its own copy
// of the vertex, so two sheets that a collapse made touch along an edge or at a vertex come
// apart. Returns the input vertex of every output vertex (#V_out; new copies are appended).
Eigen::VectorXi splitNonManifold(TriMesh& mesh);

// Moves apart vertices closer than `minDistance` (metres): each moves by minDistance towards the
// centroid of its own one-ring, so sheets that touch (copies made by splitNonManifold, or
// near-duplicate level-set vertices) stay apart when a reader welds coincident vertices.
// Returns how many vertices moved.
int separateCoincidentVertices(TriMesh& mesh, double minDistance);

// Lifts the middle corner of every nearly flat triangle (height under lift / 2 above its longest
// edge) by `lift` metres towards its one-ring centroid, so no reader drops it as degenerate.
// Returns how many corners moved.
int liftFlatFaces(TriMesh& mesh, double lift);

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
