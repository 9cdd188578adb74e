#include "drape/cloth_shapes.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <vector>

namespace s2p {

GridPanel makeGridPanel(const std::string& name, int nx, int ny, double sx, double sy,
                        const Eigen::Vector3d& origin, const Eigen::Vector3d& xAxis,
                        const Eigen::Vector3d& yAxis, bool flip,
                        const std::function<bool(int, int)>& keep) {
  GridPanel g;
  g.panel.name = name;
  g.index = Eigen::MatrixXi::Constant(nx + 1, ny + 1, -1);
  // Grid points of kept cells, numbered row by row (a full grid: j·(nx+1) + i).
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      if (!keep || keep(i, j))
        for (int k = 0; k < 4; ++k) g.index(i + (k == 1 || k == 2), j + (k >= 2)) = 0;
  int nv = 0;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      if (g.index(i, j) == 0) g.index(i, j) = ++nv;
  g.index = (g.index.array() > 0).select(g.index.array() - 1, -1);  // unused points: −1
  std::vector<Eigen::Vector3i> faces;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (keep && !keep(i, j)) continue;
      const int a = g.index(i, j), b = g.index(i + 1, j), c = g.index(i + 1, j + 1),
                d = g.index(i, j + 1);
      // Alternate the diagonal (a "union jack" pattern) so bending has no preferred direction.
      if ((i + j) % 2 == 0) {
        faces.emplace_back(a, b, c);
        faces.emplace_back(a, c, d);
      } else {
        faces.emplace_back(a, b, d);
        faces.emplace_back(b, c, d);
      }
    }
  g.panel.rest2d.resize(nv, 2);
  g.panel.start.resize(nv, 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const int v = g.index(i, j);
      if (v < 0) continue;
      const double u = sx * i / nx, w = sy * j / ny;
      g.panel.rest2d.row(v) << u, w;
      g.panel.start.row(v) = (origin + u * xAxis + w * yAxis).transpose();
    }
  g.panel.F.resize(static_cast<int>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) {
    Eigen::Vector3i t = faces[f];
    if (flip) std::swap(t[1], t[2]);
    g.panel.F.row(static_cast<int>(f)) = t.transpose();
  }
  return g;
}

TriMesh makeClosedCylinder(double radius, double y0, double y1, int rings, int segments) {
  TriMesh m;
  const int side = (rings + 1) * segments;
  m.V.resize(side + 2, 3);
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double t = 2 * std::numbers::pi * s / segments;
      m.V.row(r * segments + s) << radius * std::cos(t), y0 + (y1 - y0) * r / rings,
          radius * std::sin(t);
    }
  m.V.row(side) << 0, y0, 0;
  m.V.row(side + 1) << 0, y1, 0;
  std::vector<Eigen::Vector3i> f;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      const int c = a + segments, d = b + segments;
      f.emplace_back(a, c, b);
      f.emplace_back(b, c, d);
    }
  for (int s = 0; s < segments; ++s) {
    const int a = s, b = (s + 1) % segments;
    f.emplace_back(side, a, b);
    f.emplace_back(side + 1, rings * segments + b, rings * segments + a);
  }
  m.F.resize(static_cast<int>(f.size()), 3);
  for (size_t i = 0; i < f.size(); ++i) m.F.row(static_cast<int>(i)) = f[i].transpose();
  // Orientation: flip everything if the signed volume came out negative.
  double volume = 0;
  for (int i = 0; i < m.numFaces(); ++i)
    volume +=
        Eigen::Vector3d(m.V.row(m.F(i, 0)))
            .dot(Eigen::Vector3d(m.V.row(m.F(i, 1))).cross(Eigen::Vector3d(m.V.row(m.F(i, 2)))));
  if (volume < 0) m.F.col(1).swap(m.F.col(2));
  return m;
}

DrapeInput makeTubeGarment(double width, double height, double edge, double distance,
                           double bodyRadius) {
  const int nx = std::max(1, static_cast<int>(std::lround(width / edge)));
  const int ny = std::max(1, static_cast<int>(std::lround(height / edge)));
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY();
  const double y0 = 0.1;
  GridPanel front = makeGridPanel("front", nx, ny, width, height,
                                  Eigen::Vector3d(-width / 2, y0, distance), ex, ey, false);
  GridPanel back = makeGridPanel("back", nx, ny, width, height,
                                 Eigen::Vector3d(-width / 2, y0, -distance), ex, ey, true);
  DrapeInput in;
  for (int j = 0; j <= ny; ++j) {
    in.stitches.push_back({0, front.index(0, j), 1, back.index(0, j)});
    in.stitches.push_back({0, front.index(nx, j), 1, back.index(nx, j)});
  }
  in.panels = {std::move(front.panel), std::move(back.panel)};
  const int segments = std::max(16, static_cast<int>(2 * std::numbers::pi * bodyRadius / 0.01));
  in.body = makeClosedCylinder(bodyRadius, 0.0, y0 + height + 0.1,
                               std::max(4, static_cast<int>((height + 0.2) / 0.02)), segments);
  return in;
}

DrapeInput makeShirtGarment(double edge) {
  const double torso = 0.6, sleeve = 0.25, height = 0.7, sleeveHeight = 0.2, neck = 0.2;
  const double width = torso + 2 * sleeve;
  const int nx = static_cast<int>(std::lround(width / edge));
  const int ny = static_cast<int>(std::lround(height / edge));
  const int is = static_cast<int>(std::lround(sleeve / edge));             // torso's first column
  const int ia = ny - static_cast<int>(std::lround(sleeveHeight / edge));  // armpit row
  const int in0 = static_cast<int>(std::lround((width - neck) / 2 / edge));
  const int in1 = nx - in0;
  auto keep = [&](int i, int j) { return j >= ia || (i >= is && i < nx - is); };
  const double bodyTop = 0.75, distance = 0.19;
  const double y0 = bodyTop + 0.04 - height;  // shoulders above the top: they meet over it
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY();
  GridPanel front = makeGridPanel("front", nx, ny, width, height,
                                  Eigen::Vector3d(-width / 2, y0, distance), ex, ey, false, keep);
  GridPanel back = makeGridPanel("back", nx, ny, width, height,
                                 Eigen::Vector3d(-width / 2, y0, -distance), ex, ey, true, keep);
  std::set<std::pair<int, int>> seam;  // grid points sewn front to back
  for (int j = 0; j <= ia; ++j) {
    seam.emplace(is, j);
    seam.emplace(nx - is, j);
  }
  for (int i = 0; i <= is; ++i) {
    seam.emplace(i, ia);
    seam.emplace(nx - i, ia);
  }
  for (int i = 0; i <= nx; ++i)
    if (i <= in0 || i >= in1) seam.emplace(i, ny);
  DrapeInput in;
  for (const auto& [i, j] : seam)
    if (front.index(i, j) >= 0) in.stitches.push_back({0, front.index(i, j), 1, back.index(i, j)});
  in.panels = {std::move(front.panel), std::move(back.panel)};
  in.body = makeClosedCylinder(0.15, 0.0, bodyTop, 38, 94);
  return in;
}

}  // namespace s2p
