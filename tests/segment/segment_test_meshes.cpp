#include "segment_test_meshes.h"

#include "body/level_set_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace s2p::testing {

namespace {

double capsule(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
               double r) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - a - t * ab).norm() - r;
}

double smoothMin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}

double trousers(const Eigen::Vector3d& p) {
  const double trunk = capsule(p, {0, 0.55, 0}, {0, 1.0, 0}, 0.13);
  const double left = capsule(p, {0.075, 0.05, 0}, {0.075, 0.62, 0}, 0.055);
  const double right = capsule(p, {-0.075, 0.05, 0}, {-0.075, 0.62, 0}, 0.055);
  return smoothMin(trunk, std::min(left, right), 0.02);
}

}  // namespace

TriMesh makeTrousers(double voxel) {
  return meshImplicit(trousers, Eigen::Vector3d(-0.2, -0.06, -0.2),
                      Eigen::Vector3d(0.4, 1.26, 0.4), voxel);
}

}  // namespace s2p::testing
