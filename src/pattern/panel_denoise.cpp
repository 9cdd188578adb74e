#include "pattern/panel_denoise.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/reduced_system.h"
#include "core/spd_solver.h"

namespace s2p {

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// Filters the curve through `chain` (vertex ids into X, in order) in place: the 1D operator
// (M₁ + h⁴ L₁ M₁⁻¹ L₁) with lumped lengths M₁ and the 1/length Laplacian L₁. closed: the chain is
// a loop (no vertex fixed, last → first an edge); otherwise its first and last vertices stay.
void filterCurve(Eigen::MatrixX3d& X, const std::vector<int>& chain, bool closed, double h4) {
  const int n = static_cast<int>(chain.size());
  const int edges = closed ? n : n - 1;
  if (n < (closed ? 4 : 3)) return;
  std::vector<double> len(edges);
  double total = 0;
  for (int i = 0; i < edges; ++i) {
    len[i] = (X.row(chain[(i + 1) % n]) - X.row(chain[i])).norm();
    total += len[i];
  }
  // The exact cuts leave near-coincident vertices on a seam (edges of 1e-8 m on a 1M-vertex
  // scan, where the mean is 1 mm): their masses and 1/length weights then span 10¹⁰ and the
  // factorisation returned boundary points 0.3 m off. Lengths below a twentieth of the mean
  // count as that much: a regular chain is untouched, a needle edge's two ends move together.
  const double floor = 0.05 * total / edges;
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(n);
  Triplets lt;
  for (int i = 0; i < edges; ++i) {
    const int a = i, b = (i + 1) % n;
    const double l = std::max(len[i], floor), w = 1.0 / l;
    mass(a) += 0.5 * l, mass(b) += 0.5 * l;
    lt.insert(lt.end(), {{a, a, w}, {b, b, w}, {a, b, -w}, {b, a, -w}});
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(lt.begin(), lt.end());
  Eigen::VectorXd inv = mass.cwiseInverse();
  if (!closed) inv(0) = inv(n - 1) = 0;  // the fixed ends' one-sided Laplacians: not curvature
  Eigen::SparseMatrix<double> A = h4 * (L * inv.asDiagonal() * L);
  for (int i = 0; i < n; ++i) A.coeffRef(i, i) += mass(i);
  Eigen::MatrixX3d x0(n, 3);
  for (int i = 0; i < n; ++i) x0.row(i) = X.row(chain[i]);
  const Eigen::MatrixX3d rhs = mass.asDiagonal() * x0;
  Eigen::MatrixX3d x;
  if (closed) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
    if (ldlt.info() != Eigen::Success) throw SolverError("panel denoising: curve solve failed");
    x = ldlt.solve(rhs);
  } else {
    // Ends fixed: A_II x_I = rhs_I − A_IE x_E.
    const int m = n - 2;
    Eigen::SparseMatrix<double> AII = A.block(1, 1, m, m);
    Eigen::MatrixX3d r = rhs.middleRows(1, m);
    for (int e : {0, n - 1}) r -= Eigen::MatrixXd(A.block(1, e, m, 1)) * x0.row(e);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(AII);
    if (ldlt.info() != Eigen::Success) throw SolverError("panel denoising: curve solve failed");
    x = x0;
    x.middleRows(1, m) = ldlt.solve(r);
  }
  for (int i = 0; i < n; ++i) X.row(chain[i]) = x.row(i);
}

// Cotan Laplacian (as core/laplacian.h) with each cotangent clamped to [0, 10]: the exact cuts
// leave slivers whose huge or negative cotangents would make the filter act along them only.
Eigen::SparseMatrix<double> clampedCotanLaplacian(const TriMesh& mesh) {
  Triplets t;
  t.reserve(12 * mesh.F.rows());
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int o = mesh.F(f, k), i = mesh.F(f, (k + 1) % 3), j = mesh.F(f, (k + 2) % 3);
      const Eigen::Vector3d a = mesh.V.row(i) - mesh.V.row(o), b = mesh.V.row(j) - mesh.V.row(o);
      const double cross = a.cross(b).norm();
      if (cross <= 0) continue;
      const double w = 0.5 * std::clamp(a.dot(b) / cross, 0.0, 10.0);
      t.insert(t.end(), {{i, i, w}, {j, j, w}, {i, j, -w}, {j, i, -w}});
    }
  Eigen::SparseMatrix<double> L(mesh.V.rows(), mesh.V.rows());
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

}  // namespace

TriMesh denoisePanel(const TriMesh& panel, const std::vector<int>& loop,
                     const std::vector<int>& corners, const PanelDenoiseOptions& options) {
  if (!(options.scale >= 0) || !std::isfinite(options.scale))
    throw InputError("panel denoising: the filter length must be a finite length ≥ 0 m, not " +
                     std::to_string(options.scale));
  if (!panel.V.allFinite())
    throw InputError("panel denoising: the panel has non-finite vertex coordinates");
  TriMesh out = panel;
  if (options.scale == 0 || panel.F.rows() == 0) return out;
  const double h4 = std::pow(options.scale, 4);
  const int nv = static_cast<int>(panel.V.rows());

  // === The boundary, chain by chain between corners.
  std::vector<int> cornerAt;  // positions in loop of its corners, in loop order
  {
    std::vector<char> isCorner(nv, 0);
    for (int c : corners)
      if (c >= 0 && c < nv) isCorner[c] = 1;
    for (int i = 0; i < static_cast<int>(loop.size()); ++i)
      if (isCorner[loop[i]]) cornerAt.push_back(i);
  }
  const int nl = static_cast<int>(loop.size());
  if (cornerAt.empty()) {
    filterCurve(out.V, loop, true, h4);
  } else {
    for (size_t k = 0; k < cornerAt.size(); ++k) {
      const int from = cornerAt[k];
      const int to = k + 1 < cornerAt.size() ? cornerAt[k + 1] : cornerAt[0] + nl;
      std::vector<int> chain;
      for (int i = from; i <= to; ++i) chain.push_back(loop[i % nl]);
      filterCurve(out.V, chain, false, h4);
    }
  }

  // === The interior with the boundary fixed: A_II x_I = M_I x0_I − A_IB x_B.
  std::vector<char> onBoundary(nv, 0);
  for (int v : loop) onBoundary[v] = 1;
  if (static_cast<int>(loop.size()) == nv) return out;
  Eigen::VectorXd mass = vertexAreas(panel, MassType::Barycentric);
  const double floor = 1e-2 * mass.mean();  // slivers of the exact cuts: no huge M⁻¹
  mass = mass.cwiseMax(floor);
  // The energy Σ_i |(Lx)_i|²/m_i over the interior vertices only: a boundary vertex's one-sided
  // Laplacian is not curvature (it points into the panel), and would pull the rim inwards.
  const Eigen::SparseMatrix<double> L = clampedCotanLaplacian(panel);
  Eigen::VectorXd interiorInv = mass.cwiseInverse();
  for (int v = 0; v < nv; ++v)
    if (onBoundary[v]) interiorInv(v) = 0;
  Triplets diagonal;
  for (int v = 0; v < nv; ++v) diagonal.emplace_back(v, v, mass(v));
  Eigen::SparseMatrix<double> M(nv, nv);
  M.setFromTriplets(diagonal.begin(), diagonal.end());
  const Eigen::SparseMatrix<double> A = h4 * laplacianSquared(L, interiorInv) + M;
  const ReducedSystem system(A, onBoundary);
  SpdSolver solver;
  solver.compute(system.freeBlock());
  const Eigen::MatrixXd x0 = mass.asDiagonal() * panel.V;
  system.scatter(solver.solve(system.rhs(x0, out.V)), out.V);
  return out;
}

}  // namespace s2p
