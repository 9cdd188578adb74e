// The triangle mesh every stage exchanges: libigl's layout, plain Eigen matrices.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace s2p {

struct TriMesh {
  Eigen::MatrixX3d V;  // #V×3 vertex positions (metres once normalised)
  Eigen::MatrixX3i F;  // #F×3 vertex indices, counter-clockwise seen from outside

  int numVertices() const { return static_cast<int>(V.rows()); }
  int numFaces() const { return static_cast<int>(F.rows()); }
};

// Axis-aligned bounding box.
struct BoundingBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(0.0);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(0.0);
  Eigen::Vector3d extent() const { return max - min; }
  Eigen::Vector3d centre() const { return 0.5 * (min + max); }
};

BoundingBox boundingBox(const Eigen::MatrixX3d& V);

// The least-squares plane through points: their centroid and the eigenvectors of their
// covariance, column 0 the normal (least spread), column 2 the longest direction.
struct FittedPlane {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d normal() const { return axes.col(0); }
};
FittedPlane fitPlane(const std::vector<Eigen::Vector3d>& points);  // points non-empty

Eigen::MatrixX3d faceNormals(const TriMesh& mesh);     // #F×3 unit normals (zero for degenerate)
Eigen::VectorXd faceAreas(const TriMesh& mesh);        // #F
Eigen::MatrixX3d vertexNormals(const TriMesh& mesh);   // #V×3 angle-weighted unit normals
double surfaceArea(const TriMesh& mesh);
// Mean edge length; 0 for a mesh without faces.
double meanEdgeLength(const TriMesh& mesh);

// Throws InputError when the mesh has no faces, non-finite coordinates or an index out of
// range. `what` names the mesh in the message (e.g. the file it came from).
void validateMesh(const TriMesh& mesh, const std::string& what);

}  // namespace s2p
