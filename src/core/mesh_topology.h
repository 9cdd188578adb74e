// Connectivity of a triangle mesh, built once from F and immutable afterwards.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace s2p {

// Non-manifold elements found in a mesh.
struct ManifoldReport {
  std::vector<int> nonManifoldEdges;     // edge ids with more than two incident faces
  std::vector<int> nonManifoldVertices;  // vertices whose incident faces form more than one fan
  bool isManifold() const { return nonManifoldEdges.empty() && nonManifoldVertices.empty(); }
};

class MeshTopology {
 public:
  // F: #F×3 vertex indices; numVertices: #V (isolated vertices are allowed).
  MeshTopology(const Eigen::MatrixX3i& F, int numVertices);

  int numVertices() const { return numVertices_; }
  int numFaces() const { return static_cast<int>(F_.rows()); }
  int numEdges() const { return static_cast<int>(edges_.rows()); }

  // #E×2 unique undirected edges (v0 < v1), sorted lexicographically.
  const Eigen::MatrixX2i& edges() const { return edges_; }
  // #F×3: id of the edge opposite corner k of face f (edge between F(f,k+1) and F(f,k+2)).
  const Eigen::MatrixX3i& faceEdges() const { return faceEdges_; }
  // Faces incident to edge e (one for a boundary edge, two inside, more if non-manifold).
  std::vector<int> edgeFaces(int e) const;
  int edgeFaceCount(int e) const;
  // Faces incident to vertex v.
  std::vector<int> vertexFaces(int v) const;
  // Vertices adjacent to vertex v (one-ring), each once, in no particular order.
  std::vector<int> vertexNeighbours(int v) const;
  // Edge id of {a, b}, or -1 when there is no such edge.
  int findEdge(int a, int b) const;

  bool isBoundaryEdge(int e) const { return edgeFaceCount(e) == 1; }
  // True for vertices on at least one boundary edge.
  const std::vector<bool>& isBoundaryVertex() const { return boundaryVertex_; }

  // Boundary loops as ordered vertex cycles, oriented consistently with the faces (the
  // surface lies to the left when walking a loop seen from outside). Only well-defined on
  // manifold boundaries: at a non-manifold vertex a loop continues in the same fan (a bowtie
  // gives two triangle loops); where no continuation exists the loop is an open chain.
  const std::vector<std::vector<int>>& boundaryLoops() const { return boundaryLoops_; }

  // Connected components of faces (through shared edges or vertices): #F ids in [0, n).
  const Eigen::VectorXi& faceComponent() const { return faceComponent_; }
  int numComponents() const { return numComponents_; }

  // χ = V − E + F over referenced vertices.
  int eulerCharacteristic() const;
  const ManifoldReport& manifoldness() const { return manifold_; }
  bool isClosed() const { return boundaryLoops_.empty(); }

 private:
  Eigen::MatrixX3i F_;
  int numVertices_;
  Eigen::MatrixX2i edges_;
  Eigen::MatrixX3i faceEdges_;
  std::vector<int> edgeFaceStart_, edgeFaceList_;      // CSR edge → faces
  std::vector<int> vertexFaceStart_, vertexFaceList_;  // CSR vertex → faces
  std::vector<bool> boundaryVertex_;
  std::vector<std::vector<int>> boundaryLoops_;
  Eigen::VectorXi faceComponent_;
  int numComponents_ = 0;
  int numReferencedVertices_ = 0;
  ManifoldReport manifold_;
};

}  // namespace s2p
