// Meshes built in code: for tests with known answers, benchmarks and the demo.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

// Regular grid on [0, sx]×[0, sy] in the z = 0 plane, nx×ny cells, each split into two
// triangles; (nx+1)(ny+1) vertices, vertex (i, j) at index j*(nx+1)+i. Normals point to +z.
TriMesh makeGrid(int nx, int ny, double sx = 1.0, double sy = 1.0);

// Icosphere of the given radius centred at the origin: 10·4^level + 2 vertices, outward
// normals.
TriMesh makeIcosphere(int level, double radius = 1.0);

// Latitude-longitude sphere with poles on ±y: (rings-1)·segments + 2 vertices.
TriMesh makeUvSphere(int rings, int segments, double radius = 1.0);

// Open cylinder (no caps) around the y axis from y = 0 to y = height: (rings+1)·segments
// vertices, outward normals; two boundary loops.
TriMesh makeCylinder(int rings, int segments, double radius, double height);

// The surface of revolution about the y axis of `profile` (rows: radius, height), `segments`
// round, open at the profile's two ends; its normals point away from the axis where the profile
// rises (makeCylinder is the straight profile).
TriMesh makeRevolution(const std::vector<Eigen::Vector2d>& profile, int segments);

// Removes every face whose centroid satisfies  n·c > offset  (a planar cut making a hole).
TriMesh cutByPlane(const TriMesh& mesh, const Eigen::Vector3d& n, double offset);

// Drops unreferenced vertices, renumbering faces. Returns the old index of each new vertex.
Eigen::VectorXi removeUnreferencedVertices(TriMesh& mesh);

}  // namespace s2p
