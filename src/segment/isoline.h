// Zero isolines of a per-vertex scalar on a triangle mesh (§5.1.3: an implicit curve is a
// per-vertex scalar whose zero isoline is the curve), as polylines of points on mesh edges.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/mesh_topology.h"
#include "core/surface_point.h"
#include "core/tri_mesh.h"

namespace s2p {

// Sign rule: a vertex with φ ≥ value counts as positive (φ == value exactly is +ε), so every
// triangle has either no crossed edge or exactly two, and the isoline never passes through a
// vertex with φ < value. When a positive end has φ == value the crossing point coincides with
// that vertex (t = 0 or 1): consecutive points may then share a position (zero-length segment).

// A crossing of the isoline with mesh edge `edge` (a MeshTopology edge id, vertices
// edges()(edge, 0) < edges()(edge, 1)): position = (1 − t)·V(v0) + t·V(v1).
struct IsolinePoint {
  int edge = -1;
  double t = 0;
  SurfacePoint point;  // the same point on a face incident to the edge (bary on that face)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

// One connected piece of the isoline. Oriented so that, seen from the side the face normals
// point to, the negative region lies to the LEFT when walking from points[i] to points[i+1].
struct IsolineCurve {
  std::vector<IsolinePoint> points;
  std::vector<int> faces;  // faces[i]: the face crossed between points[i] and points[i+1]
                           // (wrapping to points[0] when closed); size n (closed) or n−1 (open)
  bool closed = true;      // false when the curve ends on the mesh border
  double length() const;   // metres, including the closing segment of a closed curve
};

struct Isoline {
  std::vector<IsolineCurve> curves;  // any number of loops and open curves
  double length() const;
  int numPoints() const;
  // All points as a #P×3 matrix (curve after curve).
  Eigen::MatrixX3d positions() const;
};

// The isoline φ = value. phi: #V, finite. Throws InputError for a wrong size or non-finite φ,
// TopologyError when a crossed edge is non-manifold or the faces around it are inconsistently
// oriented (the curve would be ambiguous there).
Isoline extractIsoline(const TriMesh& mesh, const MeshTopology& topology,
                       const Eigen::VectorXd& phi, double value = 0.0);
Isoline extractIsoline(const TriMesh& mesh, const Eigen::VectorXd& phi, double value = 0.0);

// Calls f(a, b) with the end points (Eigen::Vector3d) of every segment of every curve, closing segments
// included.
template <typename F>
void forEachSegment(const Isoline& iso, F&& f) {
  for (const IsolineCurve& c : iso.curves) {
    const size_t n = c.points.size();
    const size_t segments = c.closed ? n : (n == 0 ? 0 : n - 1);
    for (size_t i = 0; i < segments; ++i) f(c.points[i].position, c.points[(i + 1) % n].position);
  }
}

// Distance (m) from p to the nearest point of any curve (brute force over the segments); +∞
// for an isoline without curves.
double distanceToCurves(const Eigen::Vector3d& p, const Isoline& iso);

// How far one boundary lies from another: the `quantile` of the distances from every point of
// either to the other (+∞ when one has no curve). With the 95th percentile, a boundary that
// moved across a gap over a short stretch scores the width of the gap, and one nudged
// everywhere scores the nudge (the mean would average a bridged gap away).
double curveShift(const Isoline& a, const Isoline& b, double quantile = 0.95);

}  // namespace s2p
