// A sparse symmetric system with some unknowns known: A x = b where x_K is given. The known
// rows are dropped and the known columns move to the right-hand side,
//   A_FF x_F = b_F − A_FK x_K,
// which is what every Dirichlet problem on a mesh does (a harmonic extension from a boundary,
// a smoothing with its rim held, a deformation with handles). One place for the index
// bookkeeping, so that each caller keeps only its own matrix and right-hand side.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace s2p {

class ReducedSystem {
 public:
  // known: one flag per unknown of A (n×n, symmetric). The free unknowns keep their order.
  ReducedSystem(const Eigen::SparseMatrix<double>& A, const std::vector<char>& known);

  int numFree() const { return static_cast<int>(freeToFull_.size()); }
  const Eigen::SparseMatrix<double>& freeBlock() const { return Aff_; }  // A_FF
  // b_F − A_FK x_K for a full-size b (n×k) and full-size x whose known rows are read (free rows
  // ignored).
  Eigen::MatrixXd rhs(const Eigen::Ref<const Eigen::MatrixXd>& b,
                      const Eigen::Ref<const Eigen::MatrixXd>& x) const;
  // A_FK x_K alone (numFree×k).
  Eigen::MatrixXd knownPart(const Eigen::Ref<const Eigen::MatrixXd>& x) const;
  // Writes the free solution (numFree×k) into the free rows of x (n×k).
  void scatter(const Eigen::Ref<const Eigen::MatrixXd>& xFree, Eigen::Ref<Eigen::MatrixXd> x) const;
  int freeIndex(int v) const { return fullToFree_[v]; }  // −1 for a known unknown
  int fullIndex(int i) const { return freeToFull_[i]; }

 private:
  std::vector<int> fullToFree_, freeToFull_;
  Eigen::SparseMatrix<double> Aff_, Afk_;  // Afk_: numFree × n, known columns only
};

}  // namespace s2p
