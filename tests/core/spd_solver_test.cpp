#include "core/spd_solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <thread>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"

namespace s2p {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

// Rows/columns `keep` of A (keep: old index → new index or -1).
Sparse restrict(const Sparse& A, const std::vector<int>& keep, int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < A.outerSize(); ++c)
    for (Sparse::InnerIterator it(A, c); it; ++it)
      if (keep[it.row()] >= 0 && keep[it.col()] >= 0)
        t.emplace_back(keep[it.row()], keep[it.col()], it.value());
  Sparse R(n, n);
  R.setFromTriplets(t.begin(), t.end());
  return R;
}

// Dirichlet problem −Δu = f on a uniform grid with u fixed on the boundary. The cotan
// Laplacian of this triangulation is the 5-point stencil, exact for quadratics, so the discrete
// solution equals the manufactured one up to round-off.
void solveDirichlet(double (*u)(double, double), double minusLaplacian) {
  const TriMesh g = makeGrid(40, 30, 2.0, 1.5);
  const MeshTopology topo(g.F, g.numVertices());
  const Sparse L = cotanLaplacian(g);
  const Eigen::VectorXd area = vertexAreas(g);
  std::vector<int> interior(g.numVertices(), -1);
  int n = 0;
  for (int v = 0; v < g.numVertices(); ++v)
    if (!topo.isBoundaryVertex()[v]) interior[v] = n++;
  Eigen::VectorXd exact(g.numVertices());
  for (int v = 0; v < g.numVertices(); ++v) exact(v) = u(g.V(v, 0), g.V(v, 1));
  // b_I = f·A_I − L_IB u_B
  Eigen::VectorXd uBoundary = exact;
  for (int v = 0; v < g.numVertices(); ++v)
    if (interior[v] >= 0) uBoundary(v) = 0;
  const Eigen::VectorXd coupling = L * uBoundary;
  Eigen::VectorXd b(n);
  for (int v = 0; v < g.numVertices(); ++v)
    if (interior[v] >= 0) b(interior[v]) = minusLaplacian * area(v) - coupling(v);
  const Sparse A = restrict(L, interior, n);
  SpdSolver solver;
  solver.compute(A);
  ASSERT_TRUE(solver.ready());
  EXPECT_EQ(solver.rows(), n);
  const Eigen::VectorXd x = solver.solve(b);
  EXPECT_LT((A * x - b).norm(), 1e-8 * b.norm());
  for (int v = 0; v < g.numVertices(); ++v) {
    if (interior[v] < 0) continue;
    EXPECT_NEAR(x(interior[v]), exact(v), 1e-9) << v;
  }
}

TEST(SpdSolver, DirichletHarmonicProblemOnGrid) {
  solveDirichlet([](double x, double y) { return x * x - y * y + 0.5 * x * y; }, 0.0);
}

TEST(SpdSolver, DirichletPoissonProblemOnGrid) {
  // u = x² + y² + 3: −Δu = −4.
  solveDirichlet([](double x, double y) { return x * x + y * y + 3.0; }, -4.0);
}

TEST(SpdSolver, ScreenedPoissonOnSphereRecoversManufacturedSolution) {
  const TriMesh s = makeIcosphere(4, 1.0);
  const Sparse A = massMatrix(s) + 0.5 * cotanLaplacian(s);
  Eigen::VectorXd exact(s.numVertices());
  for (int v = 0; v < s.numVertices(); ++v)
    exact(v) = std::cos(3 * s.V(v, 0)) + s.V(v, 1) * s.V(v, 2);
  const Eigen::VectorXd b = A * exact;
  SpdSolver solver;
  solver.compute(A);
  const Eigen::VectorXd x = solver.solve(b);
  EXPECT_LT((A * x - b).norm(), 1e-10 * b.norm());
  EXPECT_LT((x - exact).cwiseAbs().maxCoeff(), 1e-8);
  // An Eigen expression picks the vector overload.
  const Eigen::VectorXd y = solver.solve(A * exact);
  EXPECT_LT((y - exact).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(SpdSolver, OrderingsGiveTheSameSolution) {
  const TriMesh g = makeGrid(30, 25);
  const Sparse A = massMatrix(g) + 0.2 * cotanLaplacian(g);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(g.numVertices(), -1.0, 2.0);
  SpdSolver automatic, amd(SpdSolver::Ordering::Amd), metis(SpdSolver::Ordering::Metis);
  automatic.compute(A);
  amd.compute(A);
  metis.compute(A);
  const Eigen::VectorXd x = automatic.solve(b);
  EXPECT_LT((A * x - b).norm(), 1e-10 * b.norm());
  EXPECT_LT((amd.solve(b) - x).norm(), 1e-10 * x.norm());
  EXPECT_LT((metis.solve(b) - x).norm(), 1e-10 * x.norm());
}

TEST(SpdSolver, RefactorWithNewValuesGivesNewSolution) {
  const TriMesh s = makeIcosphere(3, 1.0);
  const Sparse M = massMatrix(s), L = cotanLaplacian(s);
  const Sparse A1 = M + 1.0 * L, A2 = M + 0.01 * L;
  ASSERT_EQ(A1.nonZeros(), A2.nonZeros());
  Eigen::VectorXd b = Eigen::VectorXd::Zero(s.numVertices());
  b(0) = 1.0;
  SpdSolver solver;
  solver.compute(A1);
  const Eigen::VectorXd x1 = solver.solve(b);
  solver.refactor(A2);
  const Eigen::VectorXd x2 = solver.solve(b);
  EXPECT_LT((A2 * x2 - b).norm(), 1e-10 * b.norm());
  EXPECT_GT((x1 - x2).norm(), 0.1 * x2.norm());  // really a different system
  // Back to the first values: the first solution again.
  solver.refactor(A1);
  EXPECT_LT((solver.solve(b) - x1).norm(), 1e-12 * x1.norm());
}

TEST(SpdSolver, NonPositiveDefiniteThrows) {
  SpdSolver solver;
  Sparse minusI(3, 3);
  minusI.setIdentity();
  minusI *= -1.0;
  EXPECT_THROW(solver.compute(minusI), SolverError);
  EXPECT_FALSE(solver.ready());
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(3)), SolverError);

  Sparse indefinite(2, 2);  // eigenvalues 3 and −1
  indefinite.insert(0, 0) = 1;
  indefinite.insert(1, 0) = 2;
  indefinite.insert(0, 1) = 2;
  indefinite.insert(1, 1) = 1;
  try {
    solver.compute(indefinite);
    FAIL() << "expected SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("column"), std::string::npos);
  }
  // The analysis survives: fixing the values with the same pattern works.
  Sparse spd = indefinite;
  spd.coeffRef(1, 0) = spd.coeffRef(0, 1) = 0.5;  // [[1, .5], [.5, 1]]
  solver.refactor(spd);
  ASSERT_TRUE(solver.ready());
  const Eigen::VectorXd x = solver.solve(Eigen::Vector2d(1.5, 1.5));
  EXPECT_NEAR(x(0), 1.0, 1e-14);
  EXPECT_NEAR(x(1), 1.0, 1e-14);
}

TEST(SpdSolver, MultipleRightHandSidesEqualColumnSolves) {
  const TriMesh g = makeGrid(20, 20);
  const Sparse A = massMatrix(g) + 0.3 * cotanLaplacian(g);
  std::mt19937 rng(11);
  std::normal_distribution<double> n;
  Eigen::MatrixXd B(g.numVertices(), 5);
  for (int i = 0; i < B.size(); ++i) B.data()[i] = n(rng);
  SpdSolver solver;
  solver.compute(A);
  const Eigen::MatrixXd X = solver.solve(B);
  ASSERT_EQ(X.cols(), 5);
  for (int k = 0; k < 5; ++k) {
    const Eigen::VectorXd x = solver.solve(Eigen::VectorXd(B.col(k)));
    EXPECT_LT((X.col(k) - x).norm(), 1e-12 * x.norm());
    EXPECT_LT((A * x - B.col(k)).norm(), 1e-10 * B.col(k).norm());
  }
  EXPECT_EQ(solver.solve(Eigen::MatrixXd(g.numVertices(), 0)).cols(), 0);
}

TEST(SpdSolver, ConcurrentSolvesAgree) {
  const TriMesh s = makeIcosphere(3);
  const Sparse A = massMatrix(s) + cotanLaplacian(s);
  SpdSolver solver;
  solver.compute(A);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(s.numVertices(), 4);
  for (int k = 0; k < 4; ++k) B(10 * k, k) = 1.0;
  const Eigen::MatrixXd expected = solver.solve(B);
  std::vector<Eigen::VectorXd> got(4);
  std::vector<std::thread> threads;
  for (int k = 0; k < 4; ++k)
    threads.emplace_back([&, k] { got[k] = solver.solve(Eigen::VectorXd(B.col(k))); });
  for (auto& t : threads) t.join();
  for (int k = 0; k < 4; ++k) EXPECT_LT((got[k] - expected.col(k)).norm(), 1e-12);
}

TEST(SpdSolver, OnlyTheLowerTriangleIsRead) {
  Sparse A(2, 2), B(2, 2);
  A.insert(0, 0) = 4;
  A.insert(1, 0) = 1;
  A.insert(1, 1) = 3;  // lower triangle only
  B = A;
  B.insert(0, 1) = 99;  // garbage above the diagonal
  SpdSolver a, b;
  a.compute(A);
  b.compute(B);
  const Eigen::Vector2d rhs(5, 4);  // [[4,1],[1,3]]·(1,1)
  EXPECT_TRUE(a.solve(rhs).isApprox(Eigen::Vector2d(1, 1), 1e-14));
  EXPECT_TRUE(b.solve(rhs).isApprox(Eigen::Vector2d(1, 1), 1e-14));
}

TEST(SpdSolver, MisuseThrowsTypedErrors) {
  SpdSolver solver;
  EXPECT_FALSE(solver.ready());
  EXPECT_EQ(solver.rows(), 0);
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(2)), SolverError);
  Sparse I2(2, 2);
  I2.setIdentity();
  EXPECT_THROW(solver.refactor(I2), SolverError);  // before compute
  EXPECT_THROW(solver.compute(Sparse(2, 3)), InputError);
  EXPECT_THROW(solver.compute(Sparse(0, 0)), InputError);
  Sparse nan = I2;
  nan.coeffRef(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(solver.compute(nan), InputError);

  solver.compute(I2);
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(3)), InputError);
  Sparse other = I2;
  other.insert(1, 0) = 0.1;  // a new entry: a different pattern
  other.insert(0, 1) = 0.1;
  EXPECT_THROW(solver.refactor(other), SolverError);
  Sparse I3(3, 3);
  I3.setIdentity();
  EXPECT_THROW(solver.refactor(I3), SolverError);
  EXPECT_TRUE(solver.ready());  // a rejected refactor keeps the old factor
  EXPECT_TRUE(solver.solve(Eigen::Vector2d(2, 3)).isApprox(Eigen::Vector2d(2, 3)));
}

// A per-vertex affine fit's matrix (non-rigid ICP): the graph Laplacian of a grid times a 4×4
// weight, plus a data block v̄v̄ᵀ on each vertex. Ordered on the graph of 4×4 blocks it must
// solve as the scalar analysis does, and refactor with the same pattern.
TEST(SpdSolver, BlockOrderingSolvesLikeTheScalarOne) {
  const TriMesh g = makeGrid(25, 20, 1.0, 0.8);
  const int n = g.numVertices(), b = 4;
  auto assemble = [&](double alpha) {
    std::vector<Eigen::Triplet<double>> t;
    for (int f = 0; f < g.numFaces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int i = g.F(f, k), j = g.F(f, (k + 1) % 3);
        for (int r = 0; r < b; ++r) {
          const double w = alpha * (r == 3 ? 0.5 : 1.0);
          t.emplace_back(b * i + r, b * i + r, w);
          t.emplace_back(b * j + r, b * j + r, w);
          t.emplace_back(b * i + r, b * j + r, -w);
          t.emplace_back(b * j + r, b * i + r, -w);
        }
      }
    for (int v = 0; v < n; ++v) {
      const Eigen::Vector4d p(g.V(v, 0), g.V(v, 1), std::sin(7.0 * v / n), 1.0);
      for (int r = 0; r < b; ++r) {
        for (int c = 0; c < b; ++c) t.emplace_back(b * v + r, b * v + c, p[r] * p[c]);
        t.emplace_back(b * v + r, b * v + r, 1e-3);
      }
    }
    Sparse A(b * n, b * n);
    A.setFromTriplets(t.begin(), t.end());
    return A;
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd B(b * n, 3);
  for (int i = 0; i < B.size(); ++i) B.data()[i] = u(rng);
  for (double alpha : {50.0, 0.2}) {
    const Sparse A = assemble(alpha);
    SpdSolver scalar, blocked;
    scalar.compute(A);
    blocked.compute(A, b);
    const Eigen::MatrixXd X = blocked.solve(B);
    EXPECT_LT((A * X - B).norm(), 1e-9 * B.norm()) << alpha;
    EXPECT_LT((X - scalar.solve(B)).norm(), 1e-9 * X.norm()) << alpha;
  }
  SpdSolver blocked;
  blocked.compute(assemble(50.0), b);
  const Sparse soft = assemble(0.2);
  blocked.refactor(soft);  // the same pattern: the block analysis is kept
  EXPECT_LT((soft * blocked.solve(B) - B).norm(), 1e-9 * B.norm());
  ASSERT_NE(soft.rows() % 5, 0);
  EXPECT_THROW(blocked.compute(soft, 5), InputError);  // 4n rows that are not 5×5 blocks
  EXPECT_THROW(blocked.compute(soft, 0), InputError);
}

TEST(SpdSolver, MoveKeepsTheFactor) {
  Sparse A(2, 2);
  A.insert(0, 0) = 2;
  A.insert(1, 1) = 4;
  SpdSolver a;
  a.compute(A);
  SpdSolver b = std::move(a);
  EXPECT_TRUE(b.ready());
  EXPECT_TRUE(b.solve(Eigen::Vector2d(2, 4)).isApprox(Eigen::Vector2d(1, 1)));
  EXPECT_FALSE(a.ready());  // NOLINT(bugprone-use-after-move): moved-from is empty
  EXPECT_THROW(a.solve(Eigen::Vector2d(1, 1)), SolverError);
  SpdSolver c;
  c = std::move(b);
  EXPECT_EQ(c.rows(), 2);
  a.compute(A);  // a moved-from solver can be reused
  EXPECT_TRUE(a.ready());
}

}  // namespace
}  // namespace s2p
