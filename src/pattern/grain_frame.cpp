#include "pattern/grain_frame.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "core/error.h"

namespace s2p {

GrainFrames grainFrames(const TriMesh& panel, const Eigen::Vector3d& grain) {
  if (!grain.allFinite() || grain.norm() == 0.0)
    throw InputError(
        fmt::format("grainFrames: the grain ({}, {}, {}) must be a finite non-zero "
                    "vector (the panel's vertical)",
                    grain.x(), grain.y(), grain.z()));
  const Eigen::Vector3d g = grain.normalized();
  const int nF = panel.numFaces();
  GrainFrames frames;
  frames.warp.resize(nF, 3);
  frames.weft.resize(nF, 3);
  frames.gradients.setZero(nF, 6);
  frames.area.resize(nF);
  for (int f = 0; f < nF; ++f) {
    const Eigen::Vector3d p0 = panel.V.row(panel.F(f, 0)).transpose();
    const Eigen::Vector3d e1 = panel.V.row(panel.F(f, 1)).transpose() - p0;
    const Eigen::Vector3d e2 = panel.V.row(panel.F(f, 2)).transpose() - p0;
    const Eigen::Vector3d cross = e1.cross(e2);
    const double doubleArea = cross.norm();
    frames.area(f) = 0.5 * doubleArea;
    const Eigen::Vector3d n =
        doubleArea > 0.0 ? Eigen::Vector3d(cross / doubleArea) : Eigen::Vector3d::UnitZ();
    Eigen::Vector3d u = g - g.dot(n) * n;
    if (u.norm() < 1e-9) u = e1;  // the grain is normal to this face: any tangent will do
    u.normalize();
    if (!u.allFinite()) u = Eigen::Vector3d::UnitX();
    const Eigen::Vector3d v = n.cross(u);
    frames.warp.row(f) = u.transpose();
    frames.weft.row(f) = v.transpose();
    if (!(doubleArea > 0.0)) continue;
    // Corners in the (warp, weft) frame, p0 at the origin; ∇φ_i = perp(p_{i+2} − p_{i+1}) / 2A
    // with perp(x, y) = (−y, x) for a counter-clockwise triangle.
    const Eigen::Vector2d q[3] = {Eigen::Vector2d::Zero(), Eigen::Vector2d(e1.dot(u), e1.dot(v)),
                                  Eigen::Vector2d(e2.dot(u), e2.dot(v))};
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d d = q[(i + 2) % 3] - q[(i + 1) % 3];
      frames.gradients(f, 2 * i) = -d.y() / doubleArea;
      frames.gradients(f, 2 * i + 1) = d.x() / doubleArea;
    }
  }
  return frames;
}

Eigen::MatrixX4d grainJacobians(const GrainFrames& frames, const Eigen::MatrixX3i& F,
                                const Eigen::MatrixX2d& uv) {
  const int nF = static_cast<int>(F.rows());
  Eigen::MatrixX4d J = Eigen::MatrixX4d::Zero(nF, 4);
  for (int f = 0; f < nF; ++f)
    for (int i = 0; i < 3; ++i) {
      const double gx = frames.gradients(f, 2 * i), gy = frames.gradients(f, 2 * i + 1);
      const double x = uv(F(f, i), 0), y = uv(F(f, i), 1);
      J(f, 0) += x * gx;
      J(f, 1) += y * gx;
      J(f, 2) += x * gy;
      J(f, 3) += y * gy;
    }
  return J;
}

}  // namespace s2p
