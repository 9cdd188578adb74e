#include "core/tri_mesh.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "core/error.h"

namespace s2p {

BoundingBox boundingBox(const Eigen::MatrixX3d& V) {
  BoundingBox box;
  if (V.rows() == 0) return box;
  box.min = V.colwise().minCoeff().transpose();
  box.max = V.colwise().maxCoeff().transpose();
  return box;
}

FittedPlane fitPlane(const std::vector<Eigen::Vector3d>& points) {
  FittedPlane plane;
  for (const Eigen::Vector3d& p : points) plane.centre += p;
  plane.centre /= static_cast<double>(points.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) C += (p - plane.centre) * (p - plane.centre).transpose();
  plane.axes = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvectors();
  return plane;
}

Eigen::MatrixX3d faceNormals(const TriMesh& mesh) {
  Eigen::MatrixX3d N(mesh.numFaces(), 3);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d n = (mesh.V.row(mesh.F(f, 1)).transpose() - a)
                                  .cross(mesh.V.row(mesh.F(f, 2)).transpose() - a);
    const double len = n.norm();
    N.row(f) = len > 0 ? Eigen::RowVector3d(n.transpose() / len) : Eigen::RowVector3d::Zero();
  }
  return N;
}

Eigen::VectorXd faceAreas(const TriMesh& mesh) {
  Eigen::VectorXd A(mesh.numFaces());
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0));
    A(f) = 0.5 * (mesh.V.row(mesh.F(f, 1)).transpose() - a)
                     .cross(mesh.V.row(mesh.F(f, 2)).transpose() - a)
                     .norm();
  }
  return A;
}

Eigen::MatrixX3d vertexNormals(const TriMesh& mesh) {
  Eigen::MatrixX3d N = Eigen::MatrixX3d::Zero(mesh.numVertices(), 3);
  const Eigen::MatrixX3d FN = faceNormals(mesh);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = mesh.V.row(mesh.F(f, k));
      const Eigen::Vector3d e1 = mesh.V.row(mesh.F(f, (k + 1) % 3)).transpose() - p;
      const Eigen::Vector3d e2 = mesh.V.row(mesh.F(f, (k + 2) % 3)).transpose() - p;
      const double denom = e1.norm() * e2.norm();
      if (denom <= 0) continue;
      const double angle = std::acos(std::clamp(e1.dot(e2) / denom, -1.0, 1.0));
      N.row(mesh.F(f, k)) += angle * FN.row(f);
    }
  }
  for (int v = 0; v < N.rows(); ++v) {
    const double len = N.row(v).norm();
    if (len > 0) N.row(v) /= len;
  }
  return N;
}

double surfaceArea(const TriMesh& mesh) { return faceAreas(mesh).sum(); }

double meanEdgeLength(const TriMesh& mesh) {
  if (mesh.numFaces() == 0) return 0.0;
  double sum = 0;
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k)
      sum += (mesh.V.row(mesh.F(f, k)) - mesh.V.row(mesh.F(f, (k + 1) % 3))).norm();
  return sum / (3.0 * mesh.numFaces());
}

void validateMesh(const TriMesh& mesh, const std::string& what) {
  if (mesh.numFaces() == 0)
    throw InputError(fmt::format("{}: the mesh has no faces; give a triangle mesh", what));
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (!mesh.V.row(v).allFinite())
      throw InputError(fmt::format(
          "{}: vertex {} has a non-finite coordinate ({}, {}, {}); repair or re-export the mesh",
          what, v, mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2)));
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= mesh.numVertices())
        throw InputError(fmt::format("{}: face {} refers to vertex {} but the mesh has {} vertices",
                                     what, f, mesh.F(f, k), mesh.numVertices()));
}

}  // namespace s2p
