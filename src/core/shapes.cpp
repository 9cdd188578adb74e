#include "core/shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

namespace s2p {

TriMesh makeGrid(int nx, int ny, double sx, double sy) {
  TriMesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.V.row(j * (nx + 1) + i) << sx * i / nx, sy * j / ny, 0.0;
  m.F.resize(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      m.F.row(f++) << a, b, d;
      m.F.row(f++) << a, d, c;
    }
  return m;
}

TriMesh makeIcosphere(int level, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> verts = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0},
                                        {0, -1, t}, {0, 1, t},  {0, -1, -t}, {0, 1, -t},
                                        {t, 0, -1}, {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& v : verts) v.normalize();
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      verts.push_back((verts[a] + verts[b]).normalized());
      const int idx = static_cast<int>(verts.size()) - 1;
      mid.emplace(key, idx);
      return idx;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    faces = std::move(next);
  }
  TriMesh m;
  m.V.resize(static_cast<int>(verts.size()), 3);
  for (size_t i = 0; i < verts.size(); ++i) m.V.row(i) = radius * verts[i].transpose();
  m.F.resize(static_cast<int>(faces.size()), 3);
  for (size_t i = 0; i < faces.size(); ++i) m.F.row(i) << faces[i][0], faces[i][1], faces[i][2];
  return m;
}

TriMesh makeUvSphere(int rings, int segments, double radius) {
  TriMesh m;
  const int nv = (rings - 1) * segments + 2;
  m.V.resize(nv, 3);
  m.V.row(0) << 0, radius, 0;
  for (int r = 1; r < rings; ++r) {
    const double theta = std::numbers::pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * std::numbers::pi * s / segments;
      m.V.row(1 + (r - 1) * segments + s) << radius * std::sin(theta) * std::sin(phi),
          radius * std::cos(theta), radius * std::sin(theta) * std::cos(phi);
    }
  }
  m.V.row(nv - 1) << 0, -radius, 0;
  std::vector<std::array<int, 3>> faces;
  auto ring = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) faces.push_back({0, ring(1, s), ring(1, s + 1)});
  for (int r = 1; r < rings - 1; ++r)
    for (int s = 0; s < segments; ++s) {
      faces.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
      faces.push_back({ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
  for (int s = 0; s < segments; ++s) faces.push_back({nv - 1, ring(rings - 1, s + 1), ring(rings - 1, s)});
  m.F.resize(static_cast<int>(faces.size()), 3);
  for (size_t i = 0; i < faces.size(); ++i) m.F.row(i) << faces[i][0], faces[i][1], faces[i][2];
  return m;
}

TriMesh makeRevolution(const std::vector<Eigen::Vector2d>& profile, int segments) {
  TriMesh m;
  const int n = static_cast<int>(profile.size());
  m.V.resize(n * segments, 3);
  for (int r = 0; r < n; ++r)
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * std::numbers::pi * s / segments;
      m.V.row(r * segments + s) << profile[r].x() * std::sin(phi), profile[r].y(),
          profile[r].x() * std::cos(phi);
    }
  m.F.resize(2 * std::max(n - 1, 0) * segments, 3);
  int f = 0;
  for (int r = 0; r + 1 < n; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      const int c = a + segments, d = b + segments;
      m.F.row(f++) << a, b, d;
      m.F.row(f++) << a, d, c;
    }
  return m;
}

TriMesh makeCylinder(int rings, int segments, double radius, double height) {
  std::vector<Eigen::Vector2d> profile;
  for (int r = 0; r <= rings; ++r) profile.emplace_back(radius, height * r / rings);
  return makeRevolution(profile, segments);
}

Eigen::VectorXi removeUnreferencedVertices(TriMesh& mesh) {
  Eigen::VectorXi newIndex = Eigen::VectorXi::Constant(mesh.numVertices(), -1);
  int count = 0;
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (newIndex(mesh.F(f, k)) < 0) newIndex(mesh.F(f, k)) = count++;
  Eigen::VectorXi oldIndex(count);
  Eigen::MatrixX3d V(count, 3);
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (newIndex(v) >= 0) {
      oldIndex(newIndex(v)) = v;
      V.row(newIndex(v)) = mesh.V.row(v);
    }
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) mesh.F(f, k) = newIndex(mesh.F(f, k));
  mesh.V = std::move(V);
  return oldIndex;
}

TriMesh cutByPlane(const TriMesh& mesh, const Eigen::Vector3d& n, double offset) {
  std::vector<int> keep;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d c = (mesh.V.row(mesh.F(f, 0)) + mesh.V.row(mesh.F(f, 1)) +
                               mesh.V.row(mesh.F(f, 2))).transpose() / 3.0;
    if (n.dot(c) <= offset) keep.push_back(f);
  }
  TriMesh out;
  out.V = mesh.V;
  out.F.resize(static_cast<int>(keep.size()), 3);
  for (size_t i = 0; i < keep.size(); ++i) out.F.row(i) = mesh.F.row(keep[i]);
  removeUnreferencedVertices(out);
  return out;
}

}  // namespace s2p
