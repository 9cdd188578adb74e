#include "body/level_set_mesh.h"

#include <openvdb/tools/VolumeToMesh.h>

#include <Eigen/Geometry>

#include <cmath>
#include <vector>

namespace s2p {

TriMesh levelSetToMesh(const openvdb::FloatGrid& grid, double isoValue) {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(grid, points, tris, quads, isoValue, 0.0);
  TriMesh mesh;
  mesh.V.resize(static_cast<int>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    mesh.V.row(static_cast<int>(i)) << points[i].x(), points[i].y(), points[i].z();
  mesh.F.resize(static_cast<int>(tris.size() + 2 * quads.size()), 3);
  int f = 0;
  for (const auto& t : tris) mesh.F.row(f++) << t[0], t[1], t[2];
  for (const auto& q : quads) {
    const double d02 = (mesh.V.row(q[0]) - mesh.V.row(q[2])).squaredNorm();
    const double d13 = (mesh.V.row(q[1]) - mesh.V.row(q[3])).squaredNorm();
    if (d02 <= d13) {
      mesh.F.row(f++) << q[0], q[1], q[2];
      mesh.F.row(f++) << q[0], q[2], q[3];
    } else {
      mesh.F.row(f++) << q[0], q[1], q[3];
      mesh.F.row(f++) << q[1], q[2], q[3];
    }
  }
  return mesh;
}

TriMesh meshImplicit(const std::function<double(const Eigen::Vector3d&)>& f,
                     const Eigen::Vector3d& lo, const Eigen::Vector3d& size, double voxel) {
  openvdb::initialize();
  const Eigen::Vector3i n = (size / voxel).array().ceil().cast<int>();
  const float band = static_cast<float>(3 * voxel);
  auto grid = openvdb::FloatGrid::create(band);
  auto acc = grid->getAccessor();
  for (int k = 0; k <= n.z(); ++k)
    for (int j = 0; j <= n.y(); ++j)
      for (int i = 0; i <= n.x(); ++i) {
        const double v = f(lo + voxel * Eigen::Vector3d(i, j, k));
        if (std::abs(v) < band)
          acc.setValueOn(openvdb::Coord(i, j, k), static_cast<float>(v));
        else if (v < 0)
          acc.setValueOff(openvdb::Coord(i, j, k), -band);
      }
  TriMesh m = levelSetToMesh(*grid);  // index space (identity transform) mapped to the box
  m.V = ((voxel * m.V).rowwise() + lo.transpose()).eval();
  double volume = 0;
  for (int i = 0; i < m.numFaces(); ++i)
    volume += m.V.row(m.F(i, 0)).dot(
        Eigen::Vector3d(m.V.row(m.F(i, 1))).cross(Eigen::Vector3d(m.V.row(m.F(i, 2)))));
  if (volume < 0) m.F.col(1).swap(m.F.col(2));
  return m;
}

}  // namespace s2p
