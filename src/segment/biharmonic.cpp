#include "segment/biharmonic.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_topology.h"
#include "core/row_tree.h"
#include "core/spd_solver.h"

namespace s2p {

using Sparse = Eigen::SparseMatrix<double>;

namespace {

// The rows and columns of A whose flag is set (A restricted to some pieces: block diagonal, so
// the restriction is the pieces' own system).
Sparse restricted(const Sparse& A, const std::vector<int>& newIndex, int n) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(A.nonZeros()));
  for (int k = 0; k < A.outerSize(); ++k)
    for (Sparse::InnerIterator it(A, k); it; ++it) {
      const int r = newIndex[it.row()], c = newIndex[it.col()];
      if (r >= 0 && c >= 0) t.emplace_back(r, c, it.value());
    }
  Sparse out(n, n);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

}  // namespace

struct Biharmonic::Impl {
  TriMesh mesh;
  BiharmonicOptions options;
  Sparse Q;      // L M⁻¹ L + εM, with an entry (maybe 0) for every pair of a face's vertices
  double w = 0;  // penalty weight
  SpdSolver solver;
  bool analysed = false;
  std::vector<char> factoredPieces;  // per piece: part of the analysed system
  Eigen::VectorXi vertexPiece;       // #V: connected component
  int numPieces = 0;
  BiharmonicStats stats;
};

Biharmonic::Biharmonic(const TriMesh& mesh, const BiharmonicOptions& options)
    : impl_(std::make_unique<Impl>()) {
  validateMesh(mesh, "biharmonic mesh");
  if (!(options.penaltyWeight > 0) || options.maxMultiplierUpdates < 1 || !(options.tolerance > 0))
    throw InputError(
        "biharmonic: penaltyWeight and tolerance must be positive and "
        "maxMultiplierUpdates at least 1");
  Impl& d = *impl_;
  d.mesh = mesh;
  d.options = options;
  const int nV = mesh.numVertices();
  const Eigen::VectorXd area = vertexAreas(mesh);
  for (int v = 0; v < nV; ++v)
    if (!(area[v] > 0))
      throw InputError("biharmonic: vertex " + std::to_string(v) +
                       " has no area (unreferenced or only in degenerate faces); clean the mesh");
  // The operator and the pieces are found side by side. L holds an entry, maybe 0, for every
  // edge and vertex, so L M⁻¹ L holds one for every pair of vertices of a face: CᵀC of any
  // constraints lies in the pattern of Q, and each solve refactors the one analysis.
  Sparse LML;
  std::optional<MeshTopology> topo;
  tbb::parallel_invoke(
      [&] {
        // Cotangents clamped to ±1e3 (core/laplacian.h): phone_scan's 1 mm grid left faces
        // whose bilaplacian diagonal reached 1e36 beside a median of 1e4, and its seams could
        // not be solved.
        LML = laplacianSquared(cotanLaplacian(mesh, 1e3), bilaplacianWeights(area));
      },
      [&] { topo.emplace(mesh.F, nV); });
  // A tiny Tikhonov term, relative to the operator's own scale, keeps the system positive
  // definite on a connected piece that holds no constraint (an island a previous cut left):
  // u = 0 there instead of a failed factorisation. It changes constrained solutions by ~1e-12.
  // The scale is the diagonal's median: its mean, set by a few slivers of an exact cut, made
  // the term 1e-5 of the operator on jacket_layered's trousers, a screening that let every
  // constraint's influence die out within ~10 cm (a seam function zero across the legs).
  const double diagonalScale = medianAbs(LML.diagonal());
  const double eps = 1e-12 * diagonalScale / medianAbs(area);
  Sparse R(nV, nV);
  R.reserve(Eigen::VectorXi::Constant(nV, 1));
  for (int v = 0; v < nV; ++v) R.insert(v, v) = eps * area[v];
  d.Q = LML + R;
  d.w = options.penaltyWeight * diagonalScale;
  d.numPieces = topo->numComponents();
  d.vertexPiece.resize(nV);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) d.vertexPiece[mesh.F(f, k)] = topo->faceComponent()[f];
}

Biharmonic::~Biharmonic() = default;
Biharmonic::Biharmonic(Biharmonic&&) noexcept = default;
Biharmonic& Biharmonic::operator=(Biharmonic&&) noexcept = default;

const BiharmonicStats& Biharmonic::lastStats() const {
  return impl_->stats;
}

Eigen::VectorXd Biharmonic::solve(const std::vector<ValueConstraint>& constraints) {
  Impl& d = *impl_;
  const TriMesh& m = d.mesh;
  const int nV = m.numVertices(), k = static_cast<int>(constraints.size());
  if (k == 0) throw InputError("biharmonic: no constraints (a spline with no points left?)");
  std::vector<Eigen::Triplet<double>> ct;
  ct.reserve(3 * k);
  Eigen::VectorXd v(k);
  for (int i = 0; i < k; ++i) {
    const ValueConstraint& c = constraints[i];
    if (c.point.face < 0 || c.point.face >= m.numFaces())
      throw InputError("biharmonic: constraint " + std::to_string(i) + " is on face " +
                       std::to_string(c.point.face) + ", outside the mesh's " +
                       std::to_string(m.numFaces()) + " faces");
    if (!c.point.bary.allFinite() || std::abs(c.point.bary.sum() - 1) > 1e-6 ||
        !std::isfinite(c.value))
      throw InputError("biharmonic: constraint " + std::to_string(i) +
                       " has non-finite value or barycentric weights not summing to 1");
    for (int j = 0; j < 3; ++j)
      if (c.point.bary[j] != 0) ct.emplace_back(i, m.F(c.point.face, j), c.point.bary[j]);
    v[i] = c.value;
  }
  // Pieces of the mesh (a scan in pieces, or what earlier cuts left) are solved together when
  // each holds a constraint; a piece holding none is left out of the system (L M⁻¹ L is singular
  // there: constants cost nothing) and takes the value at the nearest vertex of a constrained
  // piece, as if φ carried on across the gap.
  std::vector<char> constrained(d.numPieces, 0);
  for (const ValueConstraint& c : constraints) constrained[d.vertexPiece[m.F(c.point.face, 0)]] = 1;
  std::vector<int> newIndex(nV, -1);
  int n = 0;
  for (int v = 0; v < nV; ++v)
    if (constrained[d.vertexPiece[v]]) newIndex[v] = n++;
  const bool all = n == nV;
  for (auto& t : ct) t = Eigen::Triplet<double>(t.row(), newIndex[t.col()], t.value());
  Sparse C(k, n);
  C.setFromTriplets(ct.begin(), ct.end());
  const Sparse Ct = C.transpose();
  const Sparse A = (all ? d.Q : restricted(d.Q, newIndex, n)) + d.w * Sparse(Ct * C);

  d.stats = {};
  if (d.analysed && d.factoredPieces == constrained) {
    try {
      d.solver.refactor(A);
      d.stats.refactored = true;
    } catch (const SolverError&) {  // pattern mismatch (should not happen): analyse again
      d.solver.compute(A);
    }
  } else {
    d.solver.compute(A);
    d.analysed = true;
    d.factoredPieces = constrained;
  }

  // Augmented Lagrangian: (Q + wCᵀC)u = Cᵀ(wv − y), y += w(Cu − v).
  Eigen::VectorXd y = Eigen::VectorXd::Zero(k), x;
  const double scale = std::max(1.0, v.cwiseAbs().maxCoeff());
  for (int it = 0; it < d.options.maxMultiplierUpdates; ++it) {
    x = d.solver.solve(Eigen::VectorXd(Ct * (d.w * v - y)));
    const Eigen::VectorXd r = C * x - v;
    d.stats.multiplierUpdates = it + 1;
    d.stats.maxResidual = r.cwiseAbs().maxCoeff();
    if (d.stats.maxResidual <= d.options.tolerance * scale) break;
    y += d.w * r;
  }
  if (all) return x;
  Eigen::VectorXd u(nV);
  std::vector<int> solved;
  solved.reserve(static_cast<size_t>(n));
  for (int vtx = 0; vtx < nV; ++vtx)
    if (newIndex[vtx] >= 0) {
      u[vtx] = x[newIndex[vtx]];
      solved.push_back(vtx);
    }
  d.stats.unconstrainedPieces = 0;
  for (char c : constrained) d.stats.unconstrainedPieces += !c;
  const RowCloud cloud{&m.V, &solved};
  const RowTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  std::vector<double> best(d.numPieces, std::numeric_limits<double>::infinity());
  std::vector<double> value(d.numPieces, 0.0);
  for (int vtx = 0; vtx < nV; ++vtx) {
    const int p = d.vertexPiece[vtx];
    if (constrained[p]) continue;
    const Eigen::Vector3d q = m.V.row(vtx).transpose();
    std::uint32_t i = 0;
    double dist = 0;
    tree.knnSearch(q.data(), 1, &i, &dist);
    if (dist < best[p]) {
      best[p] = dist;
      value[p] = u[solved[i]];
    }
  }
  for (int vtx = 0; vtx < nV; ++vtx)
    if (!constrained[d.vertexPiece[vtx]]) u[vtx] = value[d.vertexPiece[vtx]];
  return u;
}

Eigen::VectorXd biharmonicFunction(const TriMesh& mesh,
                                   const std::vector<ValueConstraint>& constraints,
                                   const BiharmonicOptions& options) {
  Biharmonic b(mesh, options);
  return b.solve(constraints);
}

std::vector<ValueConstraint> zeroConstraints(const Isoline& isoline) {
  std::vector<ValueConstraint> c;
  c.reserve(isoline.numPoints());
  for (const auto& curve : isoline.curves)
    for (const auto& p : curve.points) c.push_back({p.point, 0.0});
  return c;
}

}  // namespace s2p
