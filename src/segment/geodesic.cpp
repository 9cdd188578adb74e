#include "segment/geodesic.h"

#include <cmath>
#include <algorithm>
#include <array>
#include <limits>
#include <queue>
#include <string>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_topology.h"

namespace s2p {

struct HeatDistance::Impl {
  TriMesh mesh;
  int numFaces = 0;
  double t = 0;
  Eigen::SparseMatrix<double> G, D;  // (3#F)×#V gradient, #V×(3#F) integrated divergence
  SpdSolver heat, poisson;           // (M + tL), (L + εM)
  Eigen::VectorXi vertexComponent;   // #V
  int numComponents = 0;
};

HeatDistance::HeatDistance(const TriMesh& mesh, const HeatDistanceOptions& options)
    : impl_(std::make_unique<Impl>()) {
  validateMesh(mesh, "heat distance mesh");
  if (!(options.timeFactor > 0) || !std::isfinite(options.timeFactor))
    throw InputError("heat distance: timeFactor must be positive, got " +
                     std::to_string(options.timeFactor));
  Impl& d = *impl_;
  d.mesh = mesh;
  d.numFaces = mesh.numFaces();
  const MeshTopology topo(mesh.F, mesh.numVertices());
  d.vertexComponent = Eigen::VectorXi::Constant(mesh.numVertices(), -1);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) d.vertexComponent[mesh.F(f, k)] = topo.faceComponent()[f];
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (d.vertexComponent[v] < 0)
      throw InputError("heat distance: vertex " + std::to_string(v) +
                       " is referenced by no face; remove unreferenced vertices first");
  d.numComponents = topo.numComponents();

  const double h = meanEdgeLength(mesh);
  d.t = options.timeFactor * h * h;
  const Eigen::SparseMatrix<double> L = cotanLaplacian(mesh);
  const Eigen::SparseMatrix<double> M = massMatrix(mesh);
  d.G = gradientOperator(mesh);
  d.D = divergenceOperator(mesh);
  d.heat.compute(M + d.t * L);
  const double diag = boundingBox(mesh.V).extent().norm();
  d.poisson.compute(L + (1e-8 / (diag * diag)) * M);
}

HeatDistance::~HeatDistance() = default;
HeatDistance::HeatDistance(HeatDistance&&) noexcept = default;
HeatDistance& HeatDistance::operator=(HeatDistance&&) noexcept = default;

double HeatDistance::heatTime() const {
  return impl_->t;
}
int HeatDistance::numVertices() const {
  return impl_->mesh.numVertices();
}

Eigen::VectorXd HeatDistance::distance(const Isoline& curve) const {
  const Impl& d = *impl_;
  const TriMesh& m = d.mesh;
  const int nV = m.numVertices();
  // Source: δ_C in weak form, b_i = ∫_C hat_i ds, exact for the polyline inside each face.
  Eigen::VectorXd b = Eigen::VectorXd::Zero(nV);
  const auto add = [&](const IsolinePoint& p, double w) {
    const SurfacePoint& s = p.point;
    if (s.face < 0 || s.face >= m.numFaces())
      throw InputError("heat distance: curve point on face " + std::to_string(s.face) +
                       " is not on this mesh");
    for (int k = 0; k < 3; ++k) b[m.F(s.face, k)] += w * s.bary[k];
  };
  for (const IsolineCurve& c : curve.curves) {
    const size_t n = c.points.size();
    const size_t segments = c.closed ? n : (n > 0 ? n - 1 : 0);
    for (size_t i = 0; i < segments; ++i) {
      const IsolinePoint& p = c.points[i];
      const IsolinePoint& q = c.points[(i + 1) % n];
      const double len = (q.position - p.position).norm();
      add(p, 0.5 * len);
      add(q, 0.5 * len);
    }
  }
  if (!(b.sum() > 0)) throw InputError("heat distance: the curve is empty or has zero length");

  const Eigen::VectorXd u = d.heat.solve(b);
  const Eigen::VectorXd gu = d.G * u;
  Eigen::VectorXd X(3 * d.numFaces);
  for (int f = 0; f < d.numFaces; ++f) {
    const Eigen::Vector3d g(gu[f], gu[d.numFaces + f], gu[2 * d.numFaces + f]);
    const double n = g.norm();
    const Eigen::Vector3d x = n > 0 ? Eigen::Vector3d(-g / n) : Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) X[k * d.numFaces + f] = x[k];
  }
  Eigen::VectorXd phi = d.poisson.solve(Eigen::VectorXd(-(d.D * X)));

  // Per component: zero on the curve (source-weighted mean), +∞ where the curve is absent.
  Eigen::VectorXd sumB = Eigen::VectorXd::Zero(d.numComponents), sumBPhi = sumB;
  for (int v = 0; v < nV; ++v) {
    sumB[d.vertexComponent[v]] += b[v];
    sumBPhi[d.vertexComponent[v]] += b[v] * phi[v];
  }
  for (int v = 0; v < nV; ++v) {
    const int c = d.vertexComponent[v];
    phi[v] = sumB[c] > 0 ? std::abs(phi[v] - sumBPhi[c] / sumB[c])
                         : std::numeric_limits<double>::infinity();
  }
  return phi;
}

Eigen::VectorXd HeatDistance::signedDistance(const Isoline& curve,
                                             const Eigen::VectorXd& sign) const {
  if (sign.size() != numVertices())
    throw InputError("heat distance: the sign field has " + std::to_string(sign.size()) +
                     " values for " + std::to_string(numVertices()) + " vertices");
  Eigen::VectorXd phi = distance(curve);
  for (int v = 0; v < phi.size(); ++v)
    if (sign[v] < 0) phi[v] = -phi[v];
  return phi;
}

Eigen::VectorXd signedDistanceFromZeroSet(const TriMesh& mesh, const Eigen::VectorXd& field,
                                          const HeatDistanceOptions& options) {
  const HeatDistance heat(mesh, options);
  return heat.signedDistance(extractIsoline(mesh, field), field);
}

}  // namespace s2p

// === Fast marching

namespace s2p {
namespace {

using Vec3 = Eigen::Vector3d;

// Distance at C from the accepted corners A (dA) and B (dB) of one triangle: the plane wave
// d(X) = dA + n·(X − A), |n| = 1, that takes the values dA and dB at A and B and travels
// towards C, when its characteristic through C enters the triangle through AB (upwind); else
// the better of the two edge updates. Exact for planar fronts (Kimmel and Sethian 1998).
double triangleUpdate(const Vec3& A, const Vec3& B, const Vec3& C, double dA, double dB) {
  const double edges = std::min(dA + (C - A).norm(), dB + (C - B).norm());
  const Vec3 ab = B - A;
  const double c = ab.norm();
  if (c <= 0) return edges;
  const Vec3 ex = ab / c;
  const Vec3 ac = C - A;
  const double cx = ac.dot(ex);
  const double cy = (ac - cx * ex).norm();
  const double nx = (dB - dA) / c;
  if (cy <= 0 || std::abs(nx) >= 1) return edges;
  const double ny = std::sqrt(1 - nx * nx);
  const double x = cx - nx * cy / ny;  // where the characteristic through C meets AB
  if (x < 0 || x > c) return edges;
  return std::min(edges, dA + nx * cx + ny * cy);
}

double pointSegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

}  // namespace

struct FastMarchingDistance::Impl {
  int numFaces = 0;
  std::vector<Vec3> P;                     // #V positions, contiguous (the march reads each often)
  std::vector<std::array<int, 3>> F;       // #F corners
  std::vector<int> faceStart, faceList;   // faces around each vertex, CSR: faceStart is #V+1
};

FastMarchingDistance::FastMarchingDistance(const TriMesh& mesh)
    : impl_(std::make_unique<Impl>()) {
  validateMesh(mesh, "fast marching mesh");
  Impl& d = *impl_;
  const int nV = mesh.numVertices(), nF = mesh.numFaces();
  d.numFaces = nF;
  d.P.resize(nV);
  for (int v = 0; v < nV; ++v) d.P[v] = mesh.V.row(v).transpose();
  d.F.resize(nF);
  d.faceStart.assign(nV + 1, 0);
  for (int f = 0; f < nF; ++f)
    for (int k = 0; k < 3; ++k) {
      d.F[f][k] = mesh.F(f, k);
      ++d.faceStart[mesh.F(f, k) + 1];
    }
  for (int v = 0; v < nV; ++v) d.faceStart[v + 1] += d.faceStart[v];
  d.faceList.resize(3 * nF);
  std::vector<int> next(d.faceStart.begin(), d.faceStart.end() - 1);
  for (int f = 0; f < nF; ++f)
    for (int k = 0; k < 3; ++k) d.faceList[next[mesh.F(f, k)]++] = f;
}

FastMarchingDistance::~FastMarchingDistance() = default;
FastMarchingDistance::FastMarchingDistance(FastMarchingDistance&&) noexcept = default;
FastMarchingDistance& FastMarchingDistance::operator=(FastMarchingDistance&&) noexcept = default;

Eigen::VectorXd FastMarchingDistance::distance(const Isoline& curve) const {
  const Impl& m = *impl_;
  const int nV = static_cast<int>(m.P.size());
  if (curve.length() <= 0)
    throw InputError("fast marching: the source curve has zero length (no isoline?)");
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Eigen::VectorXd d = Eigen::VectorXd::Constant(nV, kInf);
  std::vector<char> accepted(nV, 0);
  // Exact in-face distances around the curve.
  for (const IsolineCurve& c : curve.curves) {
    const size_t n = c.points.size();
    for (size_t i = 0; i < c.faces.size(); ++i) {
      const int f = c.faces[i];
      if (f < 0 || f >= m.numFaces)
        throw InputError("fast marching: the curve crosses face " + std::to_string(f) +
                         ", not a face of this mesh");
      const Vec3& a = c.points[i].position;
      const Vec3& b = c.points[(i + 1) % n].position;
      for (int v : m.F[f]) d[v] = std::min(d[v], pointSegmentDistance(m.P[v], a, b));
    }
  }
  using Entry = std::pair<double, int>;
  std::vector<Entry> storage;
  storage.reserve(nV);
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap(std::greater<>{},
                                                                       std::move(storage));
  for (int v = 0; v < nV; ++v)
    if (std::isfinite(d[v])) heap.push({d[v], v});
  while (!heap.empty()) {
    const auto [dv, v] = heap.top();
    heap.pop();
    if (accepted[v] || dv > d[v]) continue;
    accepted[v] = 1;
    const Vec3& V = m.P[v];
    for (int i = m.faceStart[v]; i < m.faceStart[v + 1]; ++i) {
      const std::array<int, 3>& face = m.F[m.faceList[i]];
      for (int w : face) {
        if (accepted[w]) continue;  // v itself among them
        // The third corner of the face besides v and w.
        const int u = face[0] + face[1] + face[2] - v - w;
        const Vec3& W = m.P[w];
        double cand = d[v] + (W - V).norm();
        if (accepted[u]) cand = std::min(cand, triangleUpdate(V, m.P[u], W, d[v], d[u]));
        if (cand < d[w]) {
          d[w] = cand;
          heap.push({cand, w});
        }
      }
    }
  }
  return d;
}

Eigen::VectorXd FastMarchingDistance::signedDistance(const Isoline& curve,
                                                     const Eigen::VectorXd& sign) const {
  const int nV = static_cast<int>(impl_->P.size());
  if (sign.size() != nV)
    throw InputError("fast marching: the sign field has " + std::to_string(sign.size()) +
                     " values for " + std::to_string(nV) + " vertices");
  Eigen::VectorXd d = distance(curve);
  for (int v = 0; v < d.size(); ++v)
    if (sign[v] < 0) d[v] = -d[v];
  return d;
}

}  // namespace s2p
