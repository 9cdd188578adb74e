// Cached sparse Cholesky factorisation of a symmetric positive definite matrix (CHOLMOD,
// supernodal). Factor once, solve many times; when only the values change, refactor() keeps
// the symbolic analysis (fill-reducing ordering, supernodes) and redoes the numeric part.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

namespace s2p {

class SpdSolver {
 public:
  // Fill-reducing ordering of the symbolic analysis.
  enum class Ordering {
    Auto,  // CHOLMOD's default: AMD, plus METIS when AMD's fill is poor (large meshes)
    Amd,   // approximate minimum degree: fastest analysis, good below ~100k vertices
    Metis  // nested dissection: slower analysis, ~2× fewer flops at 200k+ vertices; for
           // matrices refactored many times
  };

  explicit SpdSolver(Ordering ordering = Ordering::Auto);
  ~SpdSolver();
  SpdSolver(const SpdSolver&) = delete;
  SpdSolver& operator=(const SpdSolver&) = delete;
  SpdSolver(SpdSolver&&) noexcept;
  SpdSolver& operator=(SpdSolver&&) noexcept;

  // Symbolic analysis + numeric factorisation of A (n×n). Only the lower triangle of A is read;
  // the upper triangle is ignored (pass a symmetric matrix). Throws InputError for a non-square,
  // empty or non-finite A, SolverError when A is not positive definite (naming the column).
  void compute(const Eigen::SparseMatrix<double>& A);
  // The same for a matrix of blockSize×blockSize blocks (blockSize unknowns per mesh vertex, as
  // in a per-vertex affine fit): the fill-reducing ordering is computed on the graph of blocks,
  // blockSize² times smaller, and each block's unknowns kept together (the analysis of a
  // 59k×59k 4×4-block matrix: 0.8 s → 0.05 s, with the same fill). Throws InputError when the
  // size is not a multiple of blockSize.
  void compute(const Eigen::SparseMatrix<double>& A, int blockSize);
  // Numeric factorisation only: A must have the same lower-triangle sparsity pattern as the
  // matrix given to compute() (explicit zeros count as entries). Throws SolverError otherwise.
  void refactor(const Eigen::SparseMatrix<double>& A);

  // x = A⁻¹b. Throws SolverError before a successful compute()/refactor(), InputError when
  // b has the wrong size. Thread-safe: concurrent solves on one factor are allowed.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  // X = A⁻¹B for n×k B, all right-hand sides in one pass (faster than k single solves).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;

  // Any other Eigen expression (e.g. solve(M * u)): picks the vector or matrix overload.
  template <typename Derived>
  auto solve(const Eigen::MatrixBase<Derived>& b) const {
    if constexpr (Derived::ColsAtCompileTime == 1)
      return solve(Eigen::VectorXd(b));
    else
      return solve(Eigen::MatrixXd(b));
  }

  int rows() const;    // n of the analysed matrix, 0 before compute()
  bool ready() const;  // a valid numeric factor is available

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace s2p
