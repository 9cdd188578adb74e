#include "segment_test_meshes.h"

#include "body/level_set_mesh.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

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
  openvdb::initialize();
  const Eigen::Vector3d lo(-0.2, -0.06, -0.2);
  const Eigen::Vector3i n = (Eigen::Vector3d(0.4, 1.26, 0.4) / voxel).array().ceil().cast<int>();
  const float band = static_cast<float>(3 * voxel);
  auto grid = openvdb::FloatGrid::create(band);
  auto acc = grid->getAccessor();
  for (int k = 0; k <= n.z(); ++k)
    for (int j = 0; j <= n.y(); ++j)
      for (int i = 0; i <= n.x(); ++i) {
        const double f = trousers(lo + voxel * Eigen::Vector3d(i, j, k));
        if (std::abs(f) < band)
          acc.setValueOn(openvdb::Coord(i, j, k), static_cast<float>(f));
        else if (f < 0)
          acc.setValueOff(openvdb::Coord(i, j, k), -band);
      }
  TriMesh m = levelSetToMesh(*grid);  // index space (identity transform) mapped to the box
  m.V = ((voxel * m.V).rowwise() + lo.transpose()).eval();
  double volume = 0;  // outward orientation: positive enclosed volume
  for (int i = 0; i < m.numFaces(); ++i)
    volume += m.V.row(m.F(i, 0)).dot(
        Eigen::Vector3d(m.V.row(m.F(i, 1))).cross(Eigen::Vector3d(m.V.row(m.F(i, 2)))));
  if (volume < 0) m.F.col(1).swap(m.F.col(2));
  return m;
}

}  // namespace s2p::testing
