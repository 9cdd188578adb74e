// Meshes with known labellings for the metric tests: an open cylinder around +y labelled by
// height (skin below, upper above) with its true boundary, the exact circle at that height.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include "core/shapes.h"
#include "eval/labelling.h"
#include "synth/truth.h"

namespace s2p::test {

struct CylinderSpec {
  int rings = 100, segments = 64;  // ring spacing 1 cm
  double radius = 0.15, height = 1.0;
};

inline Eigen::Vector3d faceCentroid(const TriMesh& m, int f) {
  return (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))).transpose() / 3.0;
}

// Faces with centroid above `h` → above, else below.
inline Eigen::VectorXi labelsByHeight(const TriMesh& m, double h, Label below = Label::Skin,
                                      Label above = Label::Upper) {
  Eigen::VectorXi l(m.numFaces());
  for (int f = 0; f < m.numFaces(); ++f)
    l(f) = static_cast<int>(faceCentroid(m, f).y() > h ? above : below);
  return l;
}

inline LabelledMesh labelledCylinder(const CylinderSpec& c, double h) {
  LabelledMesh lm;
  lm.mesh = makeCylinder(c.rings, c.segments, c.radius, c.height);
  lm.faceLabel = labelsByHeight(lm.mesh, h);
  return lm;
}

// The cylinder's cross-section at height y: a closed polygon through the ring's angles.
inline TrueBoundary circleAt(const CylinderSpec& c, double y, Label a = Label::Skin,
                             Label b = Label::Upper) {
  TrueBoundary tb;
  tb.a = a;
  tb.b = b;
  Eigen::MatrixX3d p(c.segments, 3);
  for (int s = 0; s < c.segments; ++s) {
    const double phi = 2 * std::numbers::pi * s / c.segments;
    p.row(s) << c.radius * std::sin(phi), y, c.radius * std::cos(phi);
  }
  tb.curves.push_back(p);
  tb.closed.push_back(true);
  return tb;
}

// Splits every triangle crossed by the plane y = c into three along the intersection (new
// vertices on the crossed edges), as an exact isoline cut does; faces keep their orientation.
inline TriMesh splitAtHeight(const TriMesh& m, double c) {
  std::vector<Eigen::RowVector3d> V;
  for (int v = 0; v < m.numVertices(); ++v) V.push_back(m.V.row(v));
  std::vector<Eigen::RowVector3i> F;
  std::map<std::pair<int, int>, int> edgeVertex;
  auto cutPoint = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    if (auto it = edgeVertex.find(key); it != edgeVertex.end()) return it->second;
    const double ya = m.V(a, 1) - c, yb = m.V(b, 1) - c;
    const double t = ya / (ya - yb);
    V.push_back((1 - t) * m.V.row(a) + t * m.V.row(b));
    return edgeVertex[key] = static_cast<int>(V.size()) - 1;
  };
  for (int f = 0; f < m.numFaces(); ++f) {
    int above = 0;
    for (int k = 0; k < 3; ++k) above += m.V(m.F(f, k), 1) > c;
    if (above == 0 || above == 3) {
      F.push_back(m.F.row(f));
      continue;
    }
    // The lone corner k is on its own side of the plane.
    int k = 0;
    for (; k < 3; ++k) {
      const bool side = m.V(m.F(f, k), 1) > c;
      if ((above == 1) == side) break;
    }
    const int a = m.F(f, k), b = m.F(f, (k + 1) % 3), d = m.F(f, (k + 2) % 3);
    const int ab = cutPoint(a, b), ad = cutPoint(a, d);
    F.push_back({a, ab, ad});
    F.push_back({ab, b, d});
    F.push_back({ab, d, ad});
  }
  TriMesh out;
  out.V.resize(static_cast<Eigen::Index>(V.size()), 3);
  for (std::size_t i = 0; i < V.size(); ++i) out.V.row(static_cast<Eigen::Index>(i)) = V[i];
  out.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (std::size_t i = 0; i < F.size(); ++i) out.F.row(static_cast<Eigen::Index>(i)) = F[i];
  return out;
}

// Two meshes side by side in one (vertices of the second renumbered after the first's).
inline TriMesh concatenate(const TriMesh& a, const TriMesh& b) {
  TriMesh out;
  out.V.resize(a.numVertices() + b.numVertices(), 3);
  out.V << a.V, b.V;
  out.F.resize(a.numFaces() + b.numFaces(), 3);
  out.F << a.F, (b.F.array() + a.numVertices()).matrix();
  return out;
}

// The cylinder cut exactly at y = c into two separate pieces (the seam's vertices duplicated),
// the lower piece labelled skin and the upper one upper.
inline LabelledMesh cutCylinder(const CylinderSpec& spec, double c) {
  const TriMesh split =
      splitAtHeight(makeCylinder(spec.rings, spec.segments, spec.radius, spec.height), c);
  const TriMesh lower = cutByPlane(split, Eigen::Vector3d::UnitY(), c);
  const TriMesh upper = cutByPlane(split, -Eigen::Vector3d::UnitY(), -c);
  LabelledMesh lm;
  lm.mesh = concatenate(lower, upper);
  lm.faceLabel.resize(lm.mesh.numFaces());
  lm.faceLabel.head(lower.numFaces()).setConstant(static_cast<int>(Label::Skin));
  lm.faceLabel.tail(upper.numFaces()).setConstant(static_cast<int>(Label::Upper));
  return lm;
}

inline double polygonPerimeter(const CylinderSpec& c) {
  return c.segments * 2 * c.radius * std::sin(std::numbers::pi / c.segments);
}

}  // namespace s2p::test
