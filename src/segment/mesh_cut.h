// Exact cut of a triangle mesh along the zero isoline of a per-vertex scalar (DESIGN.md "Exact
// cuts"): every crossed triangle is split along the isoline, new vertices lie on the crossed
// edges and are shared by the faces on both sides of the edge, so the cut boundary is the
// isoline itself, smooth independently of the mesh resolution.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/mesh_topology.h"
#include "core/tri_mesh.h"
#include "segment/isoline.h"

namespace s2p {

// Where a vertex of a cut part comes from: (1 − t)·V(a) + t·V(b) of the original mesh.
// An original vertex has a == b and t == 0; a vertex on a crossed edge has a < b, t ∈ [0, 1].
struct VertexOrigin {
  int a = -1, b = -1;
  double t = 0;
  bool isOriginal() const { return a == b; }
};

// One side of the cut: a mesh whose faces each lie inside one original face.
struct CutPart {
  TriMesh mesh;
  Eigen::VectorXi faceOrigin;              // #F of the part: index of the original face
  std::vector<VertexOrigin> vertexOrigin;  // #V of the part
};

struct CutResult {
  CutPart negative;  // φ < 0 (vertices with φ == 0 count as positive, see isoline.h)
  CutPart positive;  // φ ≥ 0
  Isoline isoline;   // the zero isoline the parts were cut along
};

// Splits `mesh` along φ = 0 (phi: #V). Each crossed triangle gives one triangle on the side of
// its lone corner and two (the quad split along its shorter diagonal) on the other side; the
// areas of the two parts sum to the original area. Unreferenced vertices are dropped. Throws as
// extractIsoline.
CutResult cutAlongIsoline(const TriMesh& mesh, const MeshTopology& topology,
                          const Eigen::VectorXd& phi);
CutResult cutAlongIsoline(const TriMesh& mesh, const Eigen::VectorXd& phi);

// The mesh with the zero isoline of φ inserted instead of cut open: each crossed triangle split as
// cutAlongIsoline splits it, both sides kept in one mesh that shares the new vertices, so the
// isoline runs along edges (panels are cut from a garment along several seams this way, one
// seam after another, before being taken apart).
struct RefinedMesh {
  TriMesh mesh;
  Eigen::VectorXi faceOrigin;              // #F: index of the original face
  std::vector<VertexOrigin> vertexOrigin;  // #V
  Eigen::VectorXi faceSide;                // #F: 1 on the φ ≥ 0 side, 0 on the φ < 0 side
};
// Throws as extractIsoline.
RefinedMesh refineAlongIsoline(const TriMesh& mesh, const MeshTopology& topology,
                               const Eigen::VectorXd& phi);

// A per-vertex field of the original mesh carried to the vertices of a cut or refined mesh
// (linear along the crossed edges, exact for fields linear on the triangles). values: #V of the
// original mesh.
Eigen::VectorXd carryToVertices(const std::vector<VertexOrigin>& origin,
                                const Eigen::VectorXd& values);

// φ with values within 1e-4 edge lengths of zero moved off it, so that no cut leaves a
// zero-area sliver (a vertex with no area has no row in M + βL on the next stage). Moves the
// boundary by at most 0.1 µm on a 1 mm mesh.
Eigen::VectorXd awayFromZero(Eigen::VectorXd phi, const TriMesh& mesh);

}  // namespace s2p
