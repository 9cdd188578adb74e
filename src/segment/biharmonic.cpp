#include "segment/biharmonic.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/spd_solver.h"

namespace s2p {

using Sparse = Eigen::SparseMatrix<double>;

struct Biharmonic::Impl {
  TriMesh mesh;
  BiharmonicOptions options;
  Sparse Q;      // L M⁻¹ L + εM, with explicit zeros on every face pair
  double w = 0;  // penalty weight
  SpdSolver solver;
  bool analysed = false;
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
  const Sparse L = cotanLaplacian(mesh);
  std::vector<Eigen::Triplet<double>> pattern;  // every face pair, so CᵀC ⊂ pattern(Q)
  pattern.reserve(9 * mesh.numFaces() + nV);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) pattern.emplace_back(mesh.F(f, a), mesh.F(f, b), 0.0);
  Sparse P(nV, nV);
  P.setFromTriplets(pattern.begin(), pattern.end());
  const Sparse LML = L * (area.cwiseInverse().asDiagonal() * L);
  // A tiny Tikhonov term, relative to the operator's own scale, keeps the system positive
  // definite on a connected piece that holds no constraint (an island a previous cut left):
  // u = 0 there instead of a failed factorisation. It changes constrained solutions by ~1e-12.
  const double eps = 1e-12 * LML.diagonal().mean() / area.mean();
  Sparse R(nV, nV);
  R.reserve(Eigen::VectorXi::Constant(nV, 1));
  for (int v = 0; v < nV; ++v) R.insert(v, v) = eps * area[v];
  d.Q = LML + P + R;
  d.w = options.penaltyWeight * d.Q.diagonal().mean();
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
  Sparse C(k, nV);
  C.setFromTriplets(ct.begin(), ct.end());
  const Sparse Ct = C.transpose();
  const Sparse A = d.Q + d.w * Sparse(Ct * C);

  d.stats = {};
  if (d.analysed && d.solver.rows() == nV) {
    try {
      d.solver.refactor(A);
      d.stats.refactored = true;
    } catch (const SolverError&) {  // pattern mismatch (should not happen): analyse again
      d.solver.compute(A);
    }
  } else {
    d.solver.compute(A);
    d.analysed = true;
  }

  // Augmented Lagrangian: (Q + wCᵀC)u = Cᵀ(wv − y), y += w(Cu − v).
  Eigen::VectorXd y = Eigen::VectorXd::Zero(k), u;
  const double scale = std::max(1.0, v.cwiseAbs().maxCoeff());
  for (int it = 0; it < d.options.maxMultiplierUpdates; ++it) {
    u = d.solver.solve(Eigen::VectorXd(Ct * (d.w * v - y)));
    const Eigen::VectorXd r = C * u - v;
    d.stats.multiplierUpdates = it + 1;
    d.stats.maxResidual = r.cwiseAbs().maxCoeff();
    if (d.stats.maxResidual <= d.options.tolerance * scale) break;
    y += d.w * r;
  }
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
