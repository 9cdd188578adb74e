#include "core/laplacian.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// Flat grid on [0,2]×[0,1.5] with interior vertices jittered in-plane (irregular, some obtuse
// triangles); boundary vertices stay put so the area stays 3.
TriMesh jitteredGrid(int nx, int ny, double amount, unsigned seed) {
  TriMesh g = makeGrid(nx, ny, 2.0, 1.5);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  for (int j = 1; j < ny; ++j)
    for (int i = 1; i < nx; ++i) {
      g.V(j * (nx + 1) + i, 0) += u(rng) * 2.0 / nx;
      g.V(j * (nx + 1) + i, 1) += u(rng) * 1.5 / ny;
    }
  // No triangle may flip, or the domain would overlap itself.
  const Eigen::MatrixX3d N = faceNormals(g);
  EXPECT_GT(N.col(2).minCoeff(), 0.99);
  return g;
}

double maxAbs(const Eigen::SparseMatrix<double>& A) {
  double m = 0;
  for (int k = 0; k < A.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, k); it; ++it)
      m = std::max(m, std::abs(it.value()));
  return m;
}

TEST(Laplacian, KnownEntriesOfRightTriangle) {
  TriMesh t;
  t.V.resize(3, 3);
  t.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  t.F.resize(1, 3);
  t.F << 0, 1, 2;
  const Eigen::MatrixXd L = Eigen::MatrixXd(cotanLaplacian(t));
  // Right angle at 0 (cot 0) and 45° at 1 and 2 (cot 1).
  Eigen::Matrix3d expected;
  expected << 1.0, -0.5, -0.5, -0.5, 0.5, 0.0, -0.5, 0.0, 0.5;
  EXPECT_TRUE(L.isApprox(expected, 1e-14)) << L;
  const Eigen::VectorXd a = vertexAreas(t, MassType::Voronoi);
  EXPECT_NEAR(a(0), 0.25, 1e-15);
  EXPECT_NEAR(a(1), 0.125, 1e-15);
  EXPECT_NEAR(a(2), 0.125, 1e-15);
}

TEST(Laplacian, ObtuseTriangleMixedAreas) {
  TriMesh t;
  t.V.resize(3, 3);
  t.V << 0, 0, 0, 2, 0, 0, 1, 0.2, 0;  // obtuse at vertex 2, area 0.2
  t.F.resize(1, 3);
  t.F << 0, 1, 2;
  const Eigen::VectorXd v = vertexAreas(t, MassType::Voronoi);
  EXPECT_NEAR(v(0), 0.05, 1e-15);
  EXPECT_NEAR(v(1), 0.05, 1e-15);
  EXPECT_NEAR(v(2), 0.10, 1e-15);
  const Eigen::VectorXd b = vertexAreas(t, MassType::Barycentric);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(b(i), 0.2 / 3, 1e-15);
}

TEST(Laplacian, SymmetricRowsSumToZeroAndPositiveSemiDefinite) {
  for (const TriMesh& m : {makeIcosphere(3, 0.7), jitteredGrid(12, 9, 0.2, 1)}) {
    const Eigen::SparseMatrix<double> L = cotanLaplacian(m);
    ASSERT_EQ(L.rows(), m.numVertices());
    EXPECT_LT(maxAbs(L - Eigen::SparseMatrix<double>(L.transpose())), 1e-14);
    const Eigen::VectorXd rowSums = L * Eigen::VectorXd::Ones(m.numVertices());
    EXPECT_LT(rowSums.cwiseAbs().maxCoeff(), 1e-12);
    for (int v = 0; v < m.numVertices(); ++v) EXPECT_GT(L.coeff(v, v), 0.0);
    // uᵀLu ≥ 0 for random u.
    std::mt19937 rng(5);
    std::normal_distribution<double> n;
    for (int t = 0; t < 5; ++t) {
      Eigen::VectorXd u(m.numVertices());
      for (auto& x : u) x = n(rng);
      EXPECT_GT(u.dot(L * u), 0.0);
    }
  }
}

TEST(Laplacian, LinearFunctionsAreHarmonicOnAFlatIrregularGrid) {
  const TriMesh g = jitteredGrid(15, 11, 0.2, 2);
  const Eigen::SparseMatrix<double> L = cotanLaplacian(g);
  const Eigen::VectorXd u =
      3.0 * g.V.col(0) - 2.0 * g.V.col(1) + Eigen::VectorXd::Constant(g.numVertices(), 0.5);
  const Eigen::VectorXd Lu = L * u;
  const MeshTopology topo(g.F, g.numVertices());
  int interior = 0;
  for (int v = 0; v < g.numVertices(); ++v)
    if (!topo.isBoundaryVertex()[v]) {
      EXPECT_NEAR(Lu(v), 0.0, 1e-12) << v;
      ++interior;
    }
  EXPECT_EQ(interior, 14 * 10);
  // Boundary values are not zero (the flux through the boundary), so the test is not vacuous.
  EXPECT_GT(Lu.cwiseAbs().maxCoeff(), 0.1);
  // Dirichlet energy of u = x over the [0,2]×[0,1.5] domain: ∫|∇x|² = area = 3.
  const Eigen::VectorXd x = g.V.col(0);
  EXPECT_NEAR(x.dot(L * x), 3.0, 1e-12);
}

int countObtuse(const TriMesh& m) {
  int count = 0;
  for (int f = 0; f < m.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVector3d p = m.V.row(m.F(f, k));
      if ((m.V.row(m.F(f, (k + 1) % 3)) - p).dot(m.V.row(m.F(f, (k + 2) % 3)) - p) < 0) ++count;
    }
  return count;
}

TEST(Laplacian, TotalMassIsSurfaceArea) {
  EXPECT_GT(countObtuse(jitteredGrid(10, 8, 0.24, 3)), 10);  // the mixed-area branch is used
  for (const TriMesh& m :
       {makeIcosphere(3, 1.3), jitteredGrid(10, 8, 0.24, 3), makeCylinder(5, 17, 0.4, 1.1)}) {
    const double area = surfaceArea(m);
    for (MassType type : {MassType::Voronoi, MassType::Barycentric}) {
      const Eigen::SparseMatrix<double> M = massMatrix(m, type);
      EXPECT_EQ(M.nonZeros(), m.numVertices());
      EXPECT_NEAR(M.sum(), area, 1e-12 * area);
      EXPECT_GT(vertexAreas(m, type).minCoeff(), 0.0);
    }
  }
}

TEST(Laplacian, GradientOfLinearFunctionIsExactAndConstant) {
  const TriMesh g = jitteredGrid(9, 7, 0.24, 4);
  const Eigen::SparseMatrix<double> G = gradientOperator(g);
  ASSERT_EQ(G.rows(), 3 * g.numFaces());
  ASSERT_EQ(G.cols(), g.numVertices());
  const Eigen::VectorXd u =
      1.5 * g.V.col(0) - 0.25 * g.V.col(1) + Eigen::VectorXd::Constant(g.numVertices(), 4.0);
  const Eigen::VectorXd gu = G * u;
  const Eigen::Map<const Eigen::MatrixX3d> perFace(gu.data(), g.numFaces(), 3);
  for (int f = 0; f < g.numFaces(); ++f)
    EXPECT_LT((perFace.row(f) - Eigen::RowVector3d(1.5, -0.25, 0.0)).norm(), 1e-12) << f;
  // On a tilted plane the gradient of a linear function is its projection onto the plane.
  TriMesh tilted = g;
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
  tilted.V = (g.V * R.transpose()).eval();
  const Eigen::Vector3d a(0.3, -1.0, 2.0);
  const Eigen::Vector3d n = R.col(2);
  const Eigen::Vector3d expected = a - a.dot(n) * n;
  const Eigen::VectorXd gt = gradientOperator(tilted) * (tilted.V * a);
  const Eigen::Map<const Eigen::MatrixX3d> perFaceT(gt.data(), g.numFaces(), 3);
  for (int f = 0; f < g.numFaces(); ++f)
    EXPECT_LT((perFaceT.row(f).transpose() - expected).norm(), 1e-12);
}

TEST(Laplacian, DivergenceOfGradientIsMinusLaplacian) {
  for (const TriMesh& m : {makeIcosphere(2, 0.9), jitteredGrid(8, 6, 0.24, 5)}) {
    const Eigen::SparseMatrix<double> D = divergenceOperator(m);
    ASSERT_EQ(D.rows(), m.numVertices());
    ASSERT_EQ(D.cols(), 3 * m.numFaces());
    const Eigen::SparseMatrix<double> L = cotanLaplacian(m);
    const Eigen::SparseMatrix<double> DG = D * gradientOperator(m);
    EXPECT_LT(maxAbs(DG + L), 1e-12 * maxAbs(L));
  }
}

TEST(Laplacian, SphereCoordinatesGiveMeanCurvatureNormal) {
  // On a sphere of radius r, −Δx = 2H·n with H = 1/r, so L·x ≈ 2/r · n · (vertex area).
  const double r = 2.0;
  const TriMesh s = makeIcosphere(4, r);
  const Eigen::MatrixXd LX = cotanLaplacian(s) * s.V;
  const Eigen::VectorXd A = vertexAreas(s, MassType::Voronoi);
  double worst = 0;
  for (int v = 0; v < s.numVertices(); ++v) {
    const Eigen::Vector3d n = s.V.row(v).transpose() / r;
    const Eigen::Vector3d expected = 2.0 / r * A(v) * n;
    worst = std::max(worst, (LX.row(v).transpose() - expected).norm() / expected.norm());
  }
  EXPECT_LT(worst, 0.03);
}

TEST(Laplacian, DegenerateFaceContributesNothing) {
  TriMesh t = makeGrid(2, 1);
  // Add a zero-area sliver (collinear corners along the bottom edge).
  t.F.conservativeResize(t.numFaces() + 1, 3);
  t.F.row(t.numFaces() - 1) << 0, 1, 2;
  const Eigen::SparseMatrix<double> L = cotanLaplacian(t);
  EXPECT_TRUE(Eigen::MatrixXd(L).allFinite());
  const TriMesh clean = makeGrid(2, 1);
  EXPECT_LT(maxAbs(L - cotanLaplacian(clean)), 1e-14);
  const Eigen::MatrixXd G = Eigen::MatrixXd(gradientOperator(t));
  EXPECT_TRUE(G.allFinite());
  const int last = t.numFaces() - 1;
  for (int d = 0; d < 3; ++d) EXPECT_EQ(G.row(d * t.numFaces() + last).norm(), 0.0);
  EXPECT_GT(G.row(0).norm(), 0.0);
}

TEST(Laplacian, BadIndicesThrow) {
  TriMesh t = makeGrid(1, 1);
  t.F(1, 2) = 9;
  EXPECT_THROW(cotanLaplacian(t), InputError);
  EXPECT_THROW(massMatrix(t), InputError);
  EXPECT_THROW(gradientOperator(t), InputError);
}

TEST(Laplacian, LaplacianSquaredIsTheProductLWL) {
  const TriMesh m = makeIcosphere(3);
  const Eigen::SparseMatrix<double> L = cotanLaplacian(m);
  const Eigen::VectorXd w = vertexAreas(m).cwiseInverse();
  const Eigen::SparseMatrix<double> expected = L * w.asDiagonal() * L;
  const Eigen::SparseMatrix<double> got = laplacianSquared(L, w);
  EXPECT_LT((got - expected).norm(), 1e-12 * expected.norm());
  EXPECT_EQ(got.nonZeros(), expected.nonZeros());
  EXPECT_THROW(laplacianSquared(L, Eigen::VectorXd::Ones(3)), InputError);
}

TEST(Laplacian, BilaplacianWeightsFloorSliversAtAFractionOfTheMedianArea) {
  Eigen::VectorXd area(5);
  area << 4e-5, 1e-10, 2e-5, 3e-5, 5e-5;  // median 3e-5
  EXPECT_DOUBLE_EQ(medianAbs(area), 3e-5);
  const Eigen::VectorXd w = bilaplacianWeights(area, 0.01);
  EXPECT_DOUBLE_EQ(w[0], 1 / 4e-5);
  EXPECT_DOUBLE_EQ(w[1], 1 / 3e-7);  // the sliver weighs as 1 % of the median
  EXPECT_DOUBLE_EQ(w[4], 1 / 5e-5);
  EXPECT_DOUBLE_EQ(medianAbs(Eigen::VectorXd()), 0.0);
  EXPECT_THROW(bilaplacianWeights(Eigen::VectorXd::Zero(3)), InputError);
}

}  // namespace
}  // namespace s2p
