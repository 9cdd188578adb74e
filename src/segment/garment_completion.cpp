#include "segment/garment_completion.h"

#include <Eigen/SparseCore>
#include <algorithm>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/reduced_system.h"
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
  // Known displacement per vertex (rim: towards its target; fixed: zero).
  std::vector<char> known(n, 0);
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
  if (std::count(known.begin(), known.end(), 1) == n) return mesh.V + D;

  const Eigen::SparseMatrix<double> L = cotanLaplacian(mesh);
  const Eigen::VectorXd area = vertexAreas(mesh);
  const Eigen::SparseMatrix<double> Q =
      laplacianSquared(L, bilaplacianWeights(area));  // ∫(Δu)² with the lumped mass
  // Q_ff d_f = −Q_fc d_c; a tiny mass term keeps free islands without constraints at rest. Its
  // scale is the diagonal's median, which no sliver sets (biharmonic.cpp says why).
  const double eps = 1e-10 * medianAbs(Q.diagonal());
  const ReducedSystem system(Q, known);
  Eigen::SparseMatrix<double> A = system.freeBlock();
  Eigen::SparseMatrix<double> I(A.rows(), A.cols());
  I.setIdentity();
  A += eps * I;
  SpdSolver solver;
  solver.compute(A);
  system.scatter(solver.solve(Eigen::MatrixXd(-system.knownPart(D))), D);
  return mesh.V + D;
}

}  // namespace s2p
