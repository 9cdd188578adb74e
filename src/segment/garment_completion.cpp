#include "segment/garment_completion.h"

#include <Eigen/SparseCore>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/spd_solver.h"

namespace s2p {

Eigen::MatrixX3d biharmonicDeformation(const TriMesh& mesh, const std::vector<int>& rim,
                                       const Eigen::MatrixX3d& rimTargets,
                                       const std::vector<bool>& fixed) {
  validateMesh(mesh, "garment completion mesh");
  const int n = mesh.numVertices();
  if (static_cast<int>(fixed.size()) != n || rimTargets.rows() != static_cast<int>(rim.size()) ||
      !rimTargets.allFinite())
    throw InputError("garment completion: " + std::to_string(fixed.size()) + " fixed flags and " +
                     std::to_string(rimTargets.rows()) + " targets for " + std::to_string(n) +
                     " vertices and " + std::to_string(rim.size()) + " rim vertices");
  // Known displacement per vertex (rim: towards its target; fixed: zero); −1 marks free.
  std::vector<int> known(n, -1);
  Eigen::MatrixX3d D = Eigen::MatrixX3d::Zero(n, 3);
  for (int v = 0; v < n; ++v)
    if (fixed[v]) known[v] = 1;
  for (size_t i = 0; i < rim.size(); ++i) {
    const int v = rim[i];
    if (v < 0 || v >= n || fixed[v])
      throw InputError("garment completion: rim vertex " + std::to_string(v) +
                       " is out of range or also fixed");
    known[v] = 1;
    D.row(v) = rimTargets.row(static_cast<int>(i)) - mesh.V.row(v);
  }
  std::vector<int> freeIndex(n, -1);
  int nf = 0;
  for (int v = 0; v < n; ++v)
    if (known[v] < 0) freeIndex[v] = nf++;
  Eigen::MatrixX3d out = mesh.V + D;
  if (nf == 0) return out;

  const Eigen::SparseMatrix<double> L = cotanLaplacian(mesh);
  const Eigen::VectorXd area = vertexAreas(mesh);
  const Eigen::SparseMatrix<double> Q =
      laplacianSquared(L, area.cwiseInverse());  // ∫(Δu)² with the lumped mass
  // Q_ff d_f = −Q_fc d_c; a tiny mass term keeps free islands without constraints at rest.
  const double eps = 1e-10 * Q.diagonal().cwiseAbs().mean();
  std::vector<Eigen::Triplet<double>> ff;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(nf, 3);
  for (int k = 0; k < Q.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q, k); it; ++it) {
      const int r = static_cast<int>(it.row()), c = static_cast<int>(it.col());
      if (freeIndex[r] < 0) continue;
      if (freeIndex[c] >= 0)
        ff.emplace_back(freeIndex[r], freeIndex[c], it.value());
      else
        rhs.row(freeIndex[r]) -= it.value() * D.row(c);
    }
  for (int v = 0; v < n; ++v)
    if (freeIndex[v] >= 0) ff.emplace_back(freeIndex[v], freeIndex[v], eps);
  Eigen::SparseMatrix<double> A(nf, nf);
  A.setFromTriplets(ff.begin(), ff.end());
  SpdSolver solver;
  solver.compute(A);
  const Eigen::MatrixXd Df = solver.solve(Eigen::MatrixXd(rhs));
  for (int v = 0; v < n; ++v)
    if (freeIndex[v] >= 0) out.row(v) = mesh.V.row(v) + Df.row(freeIndex[v]);
  return out;
}

}  // namespace s2p
