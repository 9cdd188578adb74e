#include "panel_shapes.h"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/shapes.h"

namespace s2p::test {

TriMesh makePolarDisk(int rings) {
  const double twoPi = 2.0 * std::numbers::pi;
  std::vector<Eigen::Vector3d> points{Eigen::Vector3d::Zero()};
  std::vector<int> ringStart{0};
  for (int k = 1; k <= rings; ++k) {
    ringStart.push_back(static_cast<int>(points.size()));
    const int m = 6 * k;
    for (int j = 0; j < m; ++j) {
      const double a = twoPi * j / m, r = static_cast<double>(k) / rings;
      points.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
    }
  }
  std::vector<Eigen::Vector3i> faces;
  for (int k = 1; k <= rings; ++k) {
    const int mb = 6 * k, b0 = ringStart[k];
    if (k == 1) {
      for (int j = 0; j < mb; ++j) faces.emplace_back(0, b0 + j, b0 + (j + 1) % mb);
      continue;
    }
    const int ma = 6 * (k - 1), a0 = ringStart[k - 1];
    int i = 0, j = 0;
    while (i < ma || j < mb) {
      // Advance the ring whose next vertex comes first by angle (ties: the outer ring).
      const bool advanceOuter =
          j < mb && (i == ma || static_cast<double>(j + 1) / mb <= static_cast<double>(i + 1) / ma);
      if (advanceOuter) {
        faces.emplace_back(a0 + i % ma, b0 + j, b0 + (j + 1) % mb);
        ++j;
      } else {
        faces.emplace_back(a0 + i, b0 + j % mb, a0 + (i + 1) % ma);
        ++i;
      }
    }
  }
  TriMesh mesh;
  mesh.V.resize(static_cast<int>(points.size()), 3);
  for (int v = 0; v < mesh.V.rows(); ++v) mesh.V.row(v) = points[v].transpose();
  mesh.F.resize(static_cast<int>(faces.size()), 3);
  for (int f = 0; f < mesh.F.rows(); ++f) mesh.F.row(f) = faces[f].transpose();
  return mesh;
}

TriMesh makeSphericalCap(int rings, double radius, double theta0) {
  TriMesh mesh = makePolarDisk(rings);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double x = mesh.V(v, 0), y = mesh.V(v, 1);
    const double theta = std::hypot(x, y) * theta0, phi = std::atan2(y, x);
    // Plane (X, Y) → (x, −z): the disk's +z normal becomes the cap's outward +y.
    mesh.V.row(v) << radius * std::sin(theta) * std::cos(phi), radius * std::cos(theta),
        -radius * std::sin(theta) * std::sin(phi);
  }
  return mesh;
}

TriMesh makeCylinderStrip(int nx, int ny, double radius, double width, double height) {
  TriMesh mesh = makeGrid(nx, ny, width, height);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double a = mesh.V(v, 0) / radius, y = mesh.V(v, 1);
    mesh.V.row(v) << radius * std::sin(a), y, radius * std::cos(a);
  }
  return mesh;
}

TriMesh makeConeSector(int ns, int nphi, double alpha, double s0, double s1, double phiSpan) {
  TriMesh mesh = makeGrid(ns, nphi, s1 - s0, phiSpan);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double s = s0 + mesh.V(v, 0), phi = mesh.V(v, 1);
    mesh.V.row(v) << s * std::sin(alpha) * std::cos(phi), -s * std::cos(alpha),
        s * std::sin(alpha) * std::sin(phi);
  }
  // Orient outward: the first face's normal against the radial direction of its centroid.
  const Eigen::Vector3d a = mesh.V.row(mesh.F(0, 0)), b = mesh.V.row(mesh.F(0, 1)),
                        c = mesh.V.row(mesh.F(0, 2));
  const Eigen::Vector3d centroid = (a + b + c) / 3.0;
  const Eigen::Vector3d radial(centroid.x(), 0.0, centroid.z());
  if ((b - a).cross(c - a).dot(radial) < 0.0) mesh.F.col(1).swap(mesh.F.col(2));
  return mesh;
}

TriMesh makeSaddle(int n, double h, double c) {
  TriMesh mesh = makeGrid(n, n, 2.0 * h, 2.0 * h);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double x = mesh.V(v, 0) - h, y = mesh.V(v, 1) - h;
    mesh.V.row(v) << x, y, c * (x * x - y * y);
  }
  return mesh;
}

TriMesh makeTorsoPanel(int nx, int ny, double r0, double bulge, double h, double span,
                       double jitter) {
  TriMesh mesh = makeGrid(nx, ny, span, h);
  const double dx = span / nx, dy = h / ny;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const int v = j * (nx + 1) + i;
      double a = mesh.V(v, 0), y = mesh.V(v, 1);
      if (i > 0 && i < nx && j > 0 && j < ny) {  // a fixed pseudo-random jitter
        a += jitter * dx * std::sin(12.9898 * v + 78.233);
        y += jitter * dy * std::sin(39.3468 * v + 11.135);
      }
      const double phi = a - 0.5 * span;
      const double r = r0 + bulge * std::cos(2.0 * std::numbers::pi * y / h);
      // Azimuth about +z, increasing towards +x: the grid's +x, +y map to +x-ish, +y; normal +z.
      mesh.V.row(v) << r * std::sin(phi), y, r * std::cos(phi);
    }
  return mesh;
}

TriMesh rotated(const TriMesh& mesh, const Eigen::Matrix3d& R) {
  TriMesh out = mesh;
  out.V = mesh.V * R.transpose();
  return out;
}

}  // namespace s2p::test
