#include "core/reduced_system.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/spd_solver.h"

namespace s2p {
namespace {

// The path graph's Laplacian on n unknowns (2 on the diagonal inside, 1 at the ends, −1 off it).
Eigen::SparseMatrix<double> pathLaplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i + 1 < n; ++i) {
    t.emplace_back(i, i, 1.0);
    t.emplace_back(i + 1, i + 1, 1.0);
    t.emplace_back(i, i + 1, -1.0);
    t.emplace_back(i + 1, i, -1.0);
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

TEST(ReducedSystem, AHarmonicPathWithBothEndsKnownIsTheStraightLineBetweenThem) {
  const int n = 11;
  std::vector<char> known(n, 0);
  known[0] = known[n - 1] = 1;
  const ReducedSystem system(pathLaplacian(n), known);
  ASSERT_EQ(system.numFree(), n - 2);
  EXPECT_EQ(system.freeIndex(0), -1);
  EXPECT_EQ(system.fullIndex(0), 1);
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(n, 2);
  x.row(0) << 1.0, -2.0;
  x.row(n - 1) << 6.0, 3.0;
  SpdSolver solver;
  solver.compute(system.freeBlock());
  system.scatter(solver.solve(system.rhs(Eigen::MatrixXd::Zero(n, 2), x)), x);
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(x(i, 0), 1.0 + 0.5 * i, 1e-12);
    EXPECT_NEAR(x(i, 1), -2.0 + 0.5 * i, 1e-12);
  }
}

TEST(ReducedSystem, TheRightHandSideKeepsTheFreeRowsOfBAndSubtractsTheKnownColumns) {
  const int n = 4;
  std::vector<char> known = {0, 1, 0, 0};
  const ReducedSystem system(pathLaplacian(n), known);
  Eigen::MatrixXd b(n, 1), x(n, 1);
  b << 10, 20, 30, 40;
  x << 100, 7, 100, 100;  // free rows of x are not read
  const Eigen::MatrixXd r = system.rhs(b, x);
  ASSERT_EQ(r.rows(), 3);
  EXPECT_DOUBLE_EQ(r(0, 0), 10 + 7);  // row 0 has −1 in column 1
  EXPECT_DOUBLE_EQ(r(1, 0), 30 + 7);  // row 2 too
  EXPECT_DOUBLE_EQ(r(2, 0), 40);
}

TEST(ReducedSystem, MismatchedSizesAreRefused) {
  EXPECT_THROW(ReducedSystem(pathLaplacian(3), std::vector<char>(2, 0)), InputError);
  const ReducedSystem system(pathLaplacian(3), std::vector<char>{1, 0, 0});
  EXPECT_THROW(system.rhs(Eigen::MatrixXd::Zero(2, 1), Eigen::MatrixXd::Zero(3, 1)), InputError);
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(3, 1);
  EXPECT_THROW(system.scatter(Eigen::MatrixXd::Zero(3, 1), x), InputError);
}

}  // namespace
}  // namespace s2p
