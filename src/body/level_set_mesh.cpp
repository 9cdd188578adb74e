#include "body/level_set_mesh.h"

#include <openvdb/tools/VolumeToMesh.h>

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

}  // namespace s2p
