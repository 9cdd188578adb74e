#include "core/surface_point.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>

#include "core/error.h"

namespace s2p {
namespace {

void checkFace(int face, int numFaces, const char* what) {
  if (face < 0 || face >= numFaces)
    throw InputError(fmt::format("SurfacePoint::{}: face {} is out of range (mesh has {} faces)",
                                 what, face, numFaces));
}

// True when |ab × ac|² is negligible against the squared edge lengths (zero area, collinear).
bool isDegenerate(const Eigen::Vector3d& ab, const Eigen::Vector3d& ac) {
  const double scale = ab.squaredNorm() * ac.squaredNorm();
  return !(ab.cross(ac).squaredNorm() > 1e-24 * scale) || scale == 0.0;
}

// Closest point to p on segment [a, b] as the parameter t ∈ [0, 1] of a + t(b − a).
double segmentParameter(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return 0.0;
  return std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
}

// Best of the three edges for a zero-area triangle.
Eigen::Vector3d degenerateClosest(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double tab = segmentParameter(p, a, b), tbc = segmentParameter(p, b, c),
               tca = segmentParameter(p, c, a);
  const double dab = (a + tab * (b - a) - p).squaredNorm();
  const double dbc = (b + tbc * (c - b) - p).squaredNorm();
  const double dca = (c + tca * (a - c) - p).squaredNorm();
  if (dab <= dbc && dab <= dca) return {1 - tab, tab, 0};
  if (dbc <= dca) return {0, 1 - tbc, tbc};
  return {tca, 0, 1 - tca};
}

}  // namespace

SurfacePoint SurfacePoint::atVertex(const MeshTopology& topology, const Eigen::MatrixX3i& F,
                                    int v) {
  if (v < 0 || v >= topology.numVertices())
    throw InputError(fmt::format("SurfacePoint::atVertex: vertex {} is out of range ({} vertices)",
                                 v, topology.numVertices()));
  const std::vector<int> faces = topology.vertexFaces(v);
  if (faces.empty())
    throw InputError(fmt::format(
        "SurfacePoint::atVertex: vertex {} belongs to no face; remove unreferenced vertices", v));
  SurfacePoint sp;
  sp.face = faces.front();
  for (int k = 0; k < 3; ++k) sp.bary(k) = F(sp.face, k) == v ? 1.0 : 0.0;
  return sp;
}

SurfacePoint SurfacePoint::atVertex(const Eigen::MatrixX3i& F, int v) {
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) == v) {
        SurfacePoint sp;
        sp.face = f;
        sp.bary = Eigen::Vector3d::Unit(k);
        return sp;
      }
  throw InputError(fmt::format(
      "SurfacePoint::atVertex: vertex {} belongs to no face; remove unreferenced vertices", v));
}

Eigen::Vector3d SurfacePoint::position(const TriMesh& mesh) const {
  checkFace(face, mesh.numFaces(), "position");
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) p += bary(k) * mesh.V.row(mesh.F(face, k)).transpose();
  return p;
}

Eigen::RowVectorXd SurfacePoint::interpolate(const Eigen::MatrixX3i& F,
                                             const Eigen::MatrixXd& field) const {
  checkFace(face, static_cast<int>(F.rows()), "interpolate");
  Eigen::RowVectorXd out = Eigen::RowVectorXd::Zero(field.cols());
  for (int k = 0; k < 3; ++k) {
    if (F(face, k) >= field.rows())
      throw InputError(
          fmt::format("SurfacePoint::interpolate: field has {} rows but face {} uses vertex {}",
                      field.rows(), face, F(face, k)));
    out += bary(k) * field.row(F(face, k));
  }
  return out;
}

double SurfacePoint::interpolate(const Eigen::MatrixX3i& F, const Eigen::VectorXd& field) const {
  checkFace(face, static_cast<int>(F.rows()), "interpolate");
  double out = 0;
  for (int k = 0; k < 3; ++k) {
    if (F(face, k) >= field.size())
      throw InputError(
          fmt::format("SurfacePoint::interpolate: field has {} values but face {} uses vertex {}",
                      field.size(), face, F(face, k)));
    out += bary(k) * field(F(face, k));
  }
  return out;
}

int SurfacePoint::vertexCorner(double tol) const {
  for (int k = 0; k < 3; ++k)
    if (std::abs(bary(k) - 1.0) <= tol) return k;
  return -1;
}

Eigen::Vector3d planeBarycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d v0 = b - a, v1 = c - a, v2 = p - a;
  if (isDegenerate(v0, v1)) return degenerateClosest(p, a, b, c);
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double denom = d00 * d11 - d01 * d01;
  const double v = (d11 * d20 - d01 * d21) / denom;
  const double w = (d00 * d21 - d01 * d20) / denom;
  return {1.0 - v - w, v, w};
}

Eigen::Vector3d closestPointBarycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                        const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Voronoi regions of the triangle's features (Ericson, Real-Time Collision Detection §5.1.5).
  const Eigen::Vector3d ab = b - a, ac = c - a;
  if (isDegenerate(ab, ac)) return degenerateClosest(p, a, b, c);
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

SurfacePoint projectToFace(const TriMesh& mesh, int face, const Eigen::Vector3d& p) {
  checkFace(face, mesh.numFaces(), "projectToFace");
  SurfacePoint sp;
  sp.face = face;
  sp.bary = closestPointBarycentric(p, mesh.V.row(mesh.F(face, 0)).transpose(),
                                    mesh.V.row(mesh.F(face, 1)).transpose(),
                                    mesh.V.row(mesh.F(face, 2)).transpose());
  return sp;
}

}  // namespace s2p
