#include "core/reduced_system.h"

#include <fmt/format.h>

#include "core/error.h"

namespace s2p {

ReducedSystem::ReducedSystem(const Eigen::SparseMatrix<double>& A, const std::vector<char>& known) {
  const int n = static_cast<int>(A.rows());
  if (A.cols() != n || static_cast<int>(known.size()) != n)
    throw InputError(fmt::format("ReducedSystem: a {}×{} matrix with {} known flags", A.rows(),
                                 A.cols(), known.size()));
  fullToFree_.assign(n, -1);
  for (int v = 0; v < n; ++v)
    if (!known[v]) {
      fullToFree_[v] = static_cast<int>(freeToFull_.size());
      freeToFull_.push_back(v);
    }
  std::vector<Eigen::Triplet<double>> ff, fk;
  ff.reserve(A.nonZeros());
  for (int c = 0; c < A.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
      const int r = fullToFree_[it.row()];
      if (r < 0) continue;
      if (fullToFree_[c] >= 0)
        ff.emplace_back(r, fullToFree_[c], it.value());
      else
        fk.emplace_back(r, c, it.value());
    }
  Aff_.resize(numFree(), numFree());
  Aff_.setFromTriplets(ff.begin(), ff.end());
  Afk_.resize(numFree(), n);
  Afk_.setFromTriplets(fk.begin(), fk.end());
}

Eigen::MatrixXd ReducedSystem::knownPart(const Eigen::Ref<const Eigen::MatrixXd>& x) const {
  if (x.rows() != Afk_.cols())
    throw InputError(fmt::format("ReducedSystem: {} rows given for {} unknowns", x.rows(),
                                 Afk_.cols()));
  return Afk_ * x;  // free rows of x meet only zero columns of Afk_
}

Eigen::MatrixXd ReducedSystem::rhs(const Eigen::Ref<const Eigen::MatrixXd>& b,
                                   const Eigen::Ref<const Eigen::MatrixXd>& x) const {
  if (b.rows() != Afk_.cols())
    throw InputError(fmt::format("ReducedSystem: {} rows given for {} unknowns", b.rows(),
                                 Afk_.cols()));
  Eigen::MatrixXd out(numFree(), b.cols());
  for (int i = 0; i < numFree(); ++i) out.row(i) = b.row(freeToFull_[i]);
  return out - knownPart(x);
}

void ReducedSystem::scatter(const Eigen::Ref<const Eigen::MatrixXd>& xFree,
                            Eigen::Ref<Eigen::MatrixXd> x) const {
  if (xFree.rows() != numFree() || xFree.cols() != x.cols())
    throw InputError(fmt::format("ReducedSystem: a {}×{} solution for {} free unknowns × {}",
                                 xFree.rows(), xFree.cols(), numFree(), x.cols()));
  for (int i = 0; i < numFree(); ++i) x.row(freeToFull_[i]) = xFree.row(i);
}

}  // namespace s2p
