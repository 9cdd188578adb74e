#include "segment/isoline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace s2p {

double IsolineCurve::length() const {
  double len = 0;
  for (size_t i = 1; i < points.size(); ++i)
    len += (points[i].position - points[i - 1].position).norm();
  if (closed && points.size() > 1) len += (points.front().position - points.back().position).norm();
  return len;
}

double Isoline::length() const {
  double len = 0;
  for (const auto& c : curves) len += c.length();
  return len;
}

int Isoline::numPoints() const {
  int n = 0;
  for (const auto& c : curves) n += static_cast<int>(c.points.size());
  return n;
}

Eigen::MatrixX3d Isoline::positions() const {
  Eigen::MatrixX3d P(numPoints(), 3);
  int i = 0;
  for (const auto& c : curves)
    for (const auto& p : c.points) P.row(i++) = p.position;
  return P;
}

Isoline extractIsoline(const TriMesh& mesh, const Eigen::VectorXd& phi, double value) {
  const MeshTopology topology(mesh.F, mesh.numVertices());
  return extractIsoline(mesh, topology, phi, value);
}

Isoline extractIsoline(const TriMesh& mesh, const MeshTopology& topology,
                       const Eigen::VectorXd& phi, double value) {
  const int nV = mesh.numVertices(), nF = mesh.numFaces(), nE = topology.numEdges();
  if (phi.size() != nV)
    throw InputError("isoline: the scalar field has " + std::to_string(phi.size()) +
                     " values but the mesh has " + std::to_string(nV) + " vertices");
  if (topology.numFaces() != nF || topology.numVertices() != nV)
    throw InputError("isoline: the topology was built for another mesh");
  for (int v = 0; v < nV; ++v)
    if (!std::isfinite(phi[v]))
      throw InputError("isoline: the scalar field is not finite at vertex " + std::to_string(v));
  if (!std::isfinite(value)) throw InputError("isoline: the iso value is not finite");

  const auto positive = [&](int v) { return phi[v] >= value; };
  const Eigen::MatrixX3i& FE = topology.faceEdges();
  std::vector<int> outFace(nE, -1), inFace(nE, -1);  // face whose segment leaves / enters edge e
  std::vector<int> segEnd(nF, -1);                   // edge where the segment of face f ends
  for (int f = 0; f < nF; ++f) {
    const bool s0 = positive(mesh.F(f, 0)), s1 = positive(mesh.F(f, 1)),
               s2 = positive(mesh.F(f, 2));
    if (s0 == s1 && s1 == s2) continue;
    const int k = (s0 != s1 && s0 != s2) ? 0 : (s1 != s0 && s1 != s2) ? 1 : 2;  // lone corner
    const int eNext = FE(f, (k + 2) % 3);                                       // edge (k, k+1)
    const int ePrev = FE(f, (k + 1) % 3);                                       // edge (k+2, k)
    const bool loneNegative = !positive(mesh.F(f, k));
    const int from = loneNegative ? eNext : ePrev, to = loneNegative ? ePrev : eNext;
    for (int e : {from, to})
      if (topology.edgeFaceCount(e) > 2)
        throw TopologyError("isoline: the curve crosses non-manifold edge " + std::to_string(e) +
                            " (vertices " + std::to_string(topology.edges()(e, 0)) + ", " +
                            std::to_string(topology.edges()(e, 1)) +
                            "); repair the mesh (e.g. scan cleanup) first");
    if (outFace[from] >= 0 || inFace[to] >= 0)
      throw TopologyError("isoline: faces " + std::to_string(f) + " and " +
                          std::to_string(outFace[from] >= 0 ? outFace[from] : inFace[to]) +
                          " are inconsistently oriented; orient the mesh first");
    outFace[from] = f;
    inFace[to] = f;
    segEnd[f] = to;
  }

  const auto makePoint = [&](int e, int face) {
    IsolinePoint p;
    p.edge = e;
    const int a = topology.edges()(e, 0), b = topology.edges()(e, 1);
    const double fa = phi[a] - value, fb = phi[b] - value;
    p.t = std::clamp(fa / (fa - fb), 0.0, 1.0);
    p.position = (1 - p.t) * mesh.V.row(a).transpose() + p.t * mesh.V.row(b).transpose();
    p.point.face = face;
    for (int k = 0; k < 3; ++k) {
      if (mesh.F(face, k) == a) p.point.bary[k] = 1 - p.t;
      if (mesh.F(face, k) == b) p.point.bary[k] = p.t;
    }
    return p;
  };

  Isoline iso;
  std::vector<char> visited(nE, 0);
  const auto trace = [&](int start) {
    IsolineCurve c;
    int e = start;
    while (true) {
      visited[e] = 1;
      const int f = outFace[e];
      c.points.push_back(makePoint(e, f >= 0 ? f : inFace[e]));
      if (f < 0) {
        c.closed = false;
        break;
      }
      c.faces.push_back(f);
      e = segEnd[f];
      if (e == start) break;
    }
    iso.curves.push_back(std::move(c));
  };
  for (int e = 0; e < nE; ++e)  // open curves first: they start on the border
    if (outFace[e] >= 0 && inFace[e] < 0) trace(e);
  for (int e = 0; e < nE; ++e)
    if (outFace[e] >= 0 && !visited[e]) trace(e);
  return iso;
}

double distanceToCurves(const Eigen::Vector3d& p, const Isoline& iso) {
  double best = std::numeric_limits<double>::infinity();
  forEachSegment(iso, [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * ab - p).norm());
  });
  for (const IsolineCurve& c : iso.curves)
    if (c.points.size() == 1) best = std::min(best, (c.points[0].position - p).norm());
  return best;
}

double curveShift(const Isoline& a, const Isoline& b, double quantile) {
  if (a.curves.empty() || b.curves.empty()) return std::numeric_limits<double>::infinity();
  std::vector<double> d;
  for (const auto* pair : {&a, &b}) {
    const Isoline& to = pair == &a ? b : a;
    for (const IsolineCurve& c : pair->curves)
      for (const IsolinePoint& p : c.points) d.push_back(distanceToCurves(p.position, to));
  }
  if (d.empty()) return 0.0;
  const double q = std::clamp(quantile, 0.0, 1.0);
  const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(d.size() - 1));
  std::nth_element(d.begin(), d.begin() + k, d.end());
  return d[static_cast<size_t>(k)];
}

}  // namespace s2p
