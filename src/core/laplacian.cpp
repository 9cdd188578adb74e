#include "core/laplacian.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"

namespace s2p {
namespace {

void checkIndices(const TriMesh& mesh, const char* what) {
  const int nV = mesh.numVertices();
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= nV)
        throw InputError(
            fmt::format("{}: face {} references vertex {} but the mesh has {} "
                        "vertices; fix the face indices",
                        what, f, mesh.F(f, k), nV));
}

Eigen::Vector3d corner(const TriMesh& mesh, int f, int k) {
  return mesh.V.row(mesh.F(f, k)).transpose();
}

// Squared-area threshold below which a face is treated as degenerate (relative to its edges).
bool degenerate(double cross2, double scale2) {
  return !(cross2 > 1e-28 * scale2);
}

}  // namespace

Eigen::SparseMatrix<double> cotanLaplacian(const TriMesh& mesh, double maxCotangent) {
  checkIndices(mesh, "cotanLaplacian");
  const int nV = mesh.numVertices(), nF = mesh.numFaces();
  // Off-diagonal entries bucketed by column (counting sort), then merged per column: a direct
  // CSC build that avoids setFromTriplets' extra passes. 6 entries per face.
  std::vector<int> colStart(nV + 1, 0);
  for (int f = 0; f < nF; ++f)
    for (int k = 0; k < 3; ++k) colStart[mesh.F(f, k) + 1] += 2;
  for (int v = 0; v < nV; ++v) colStart[v + 1] += colStart[v];
  std::vector<int> rowOf(colStart[nV]);
  std::vector<double> valOf(colStart[nV]);
  std::vector<int> fill(colStart.begin(), colStart.end() - 1);
  for (int f = 0; f < nF; ++f) {
    const Eigen::Vector3d p[3] = {corner(mesh, f, 0), corner(mesh, f, 1), corner(mesh, f, 2)};
    const double cross2 = (p[1] - p[0]).cross(p[2] - p[0]).squaredNorm();
    const double scale2 = (p[1] - p[0]).squaredNorm() * (p[2] - p[0]).squaredNorm();
    const bool skip = degenerate(cross2, scale2);
    const double invDoubleArea = skip ? 0.0 : 1.0 / std::sqrt(cross2);
    for (int k = 0; k < 3; ++k) {
      const int i = mesh.F(f, (k + 1) % 3), j = mesh.F(f, (k + 2) % 3);
      // cot of the angle at corner k = (e1·e2)/|e1×e2|; the edge opposite k gets −½cot.
      const double w = skip ? 0.0
                            : -0.5 * std::clamp((p[(k + 1) % 3] - p[k]).dot(p[(k + 2) % 3] - p[k]) *
                                                    invDoubleArea,
                                                -maxCotangent, maxCotangent);
      rowOf[fill[j]] = i;
      valOf[fill[j]++] = w;
      rowOf[fill[i]] = j;
      valOf[fill[i]++] = w;
    }
  }
  // Per column: insertion-sort the (few) entries by row, merge duplicates, add the diagonal,
  // writing straight into the CSC arrays (upper bound on nnz, shrunk at the end).
  Eigen::SparseMatrix<double> L(nV, nV);
  L.resizeNonZeros(static_cast<Eigen::Index>(colStart[nV]) + nV);
  int* outer = L.outerIndexPtr();
  int* inner = L.innerIndexPtr();
  double* values = L.valuePtr();
  int nnz = 0;
  outer[0] = 0;
  for (int c = 0; c < nV; ++c) {
    const int b = colStart[c], e = colStart[c + 1];
    for (int t = b + 1; t < e; ++t) {
      const int r = rowOf[t];
      const double w = valOf[t];
      int u = t;
      for (; u > b && rowOf[u - 1] > r; --u) {
        rowOf[u] = rowOf[u - 1];
        valOf[u] = valOf[u - 1];
      }
      rowOf[u] = r;
      valOf[u] = w;
    }
    double diag = 0.0;
    bool diagWritten = false;
    for (int t = b; t < e;) {
      const int r = rowOf[t];
      double sum = 0.0;
      for (; t < e && rowOf[t] == r; ++t) sum += valOf[t];
      diag -= sum;
      if (!diagWritten && r > c) {
        inner[nnz] = c;
        values[nnz++] = 0.0;  // filled below once the column sum is known
        diagWritten = true;
      }
      inner[nnz] = r;
      values[nnz++] = sum;
    }
    if (!diagWritten) {
      inner[nnz] = c;
      values[nnz++] = 0.0;
    }
    // Place the diagonal value: it is the entry with row c in this column.
    for (int t = outer[c]; t < nnz; ++t)
      if (inner[t] == c) {
        values[t] = diag;
        break;
      }
    outer[c + 1] = nnz;
  }
  L.data().resize(nnz);
  return L;
}

Eigen::VectorXd vertexAreas(const TriMesh& mesh, MassType type) {
  checkIndices(mesh, "vertexAreas");
  Eigen::VectorXd area = Eigen::VectorXd::Zero(mesh.numVertices());
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d p[3] = {corner(mesh, f, 0), corner(mesh, f, 1), corner(mesh, f, 2)};
    const double cross = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    const double A = 0.5 * cross;
    if (type == MassType::Barycentric || !(cross > 0)) {
      for (int k = 0; k < 3; ++k) area(mesh.F(f, k)) += A / 3.0;
      continue;
    }
    // dot(k) = (p_{k+1} − p_k)·(p_{k+2} − p_k): negative iff the angle at k is obtuse.
    double dot[3];
    for (int k = 0; k < 3; ++k) dot[k] = (p[(k + 1) % 3] - p[k]).dot(p[(k + 2) % 3] - p[k]);
    const int obtuse = dot[0] < 0 ? 0 : (dot[1] < 0 ? 1 : (dot[2] < 0 ? 2 : -1));
    if (obtuse >= 0) {
      for (int k = 0; k < 3; ++k) area(mesh.F(f, k)) += (k == obtuse ? 0.5 : 0.25) * A;
      continue;
    }
    // Voronoi region of corner k: ⅛(|e_k,k+1|² cot θ_{k+2} + |e_k,k+2|² cot θ_{k+1}).
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      const double cot1 = dot[k1] / cross, cot2 = dot[k2] / cross;
      area(mesh.F(f, k)) +=
          0.125 * ((p[k1] - p[k]).squaredNorm() * cot2 + (p[k2] - p[k]).squaredNorm() * cot1);
    }
  }
  return area;
}

double medianAbs(const Eigen::VectorXd& x) {
  if (x.size() == 0) return 0.0;
  std::vector<double> a(static_cast<size_t>(x.size()));
  for (Eigen::Index i = 0; i < x.size(); ++i) a[static_cast<size_t>(i)] = std::abs(x[i]);
  const auto mid = a.begin() + static_cast<std::ptrdiff_t>(a.size() / 2);
  std::nth_element(a.begin(), mid, a.end());
  return *mid;
}

Eigen::VectorXd bilaplacianWeights(const Eigen::VectorXd& area, double floorFraction) {
  const double median = medianAbs(area);
  if (!(median > 0))
    throw InputError(
        fmt::format("bilaplacianWeights: the median of {} vertex areas is {} (an "
                    "empty or degenerate mesh)",
                    area.size(), median));
  const double floor = std::max(floorFraction, 0.0) * median;
  return area.unaryExpr([floor](double a) { return 1.0 / std::max(a, floor); });
}

Eigen::SparseMatrix<double> massMatrix(const TriMesh& mesh, MassType type) {
  const Eigen::VectorXd a = vertexAreas(mesh, type);
  Eigen::SparseMatrix<double> M(a.size(), a.size());
  M.reserve(Eigen::VectorXi::Ones(a.size()));
  for (Eigen::Index v = 0; v < a.size(); ++v) M.insert(v, v) = a(v);
  M.makeCompressed();
  return M;
}

Eigen::SparseMatrix<double> gradientOperator(const TriMesh& mesh) {
  checkIndices(mesh, "gradientOperator");
  const Eigen::Index nF = mesh.numFaces();
  // Row-major build: every row has exactly three entries (explicit zeros for degenerate faces,
  // so the pattern depends on F only), then one conversion to column-major.
  Eigen::SparseMatrix<double, Eigen::RowMajor> G(3 * nF, mesh.numVertices());
  G.resizeNonZeros(9 * nF);
  int* outer = G.outerIndexPtr();
  int* inner = G.innerIndexPtr();
  double* values = G.valuePtr();
  for (Eigen::Index r = 0; r <= 3 * nF; ++r) outer[r] = static_cast<int>(3 * r);
  for (Eigen::Index f = 0; f < nF; ++f) {
    const Eigen::Vector3d p[3] = {corner(mesh, static_cast<int>(f), 0),
                                  corner(mesh, static_cast<int>(f), 1),
                                  corner(mesh, static_cast<int>(f), 2)};
    const Eigen::Vector3d n2A = (p[1] - p[0]).cross(p[2] - p[0]);  // normal × 2·area
    const double cross2 = n2A.squaredNorm();
    const bool skip = degenerate(cross2, (p[1] - p[0]).squaredNorm() * (p[2] - p[0]).squaredNorm());
    // Corners in increasing vertex order (a row's column indices must be sorted).
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int a, int b) { return mesh.F(f, a) < mesh.F(f, b); });
    for (int slot = 0; slot < 3; ++slot) {
      const int k = order[slot];
      // ∇φ_k = n × e_k / (2A), e_k the edge opposite corner k in winding order.
      const Eigen::Vector3d g =
          skip ? Eigen::Vector3d::Zero()
               : Eigen::Vector3d(n2A.cross(p[(k + 2) % 3] - p[(k + 1) % 3]) / cross2);
      for (int d = 0; d < 3; ++d) {
        const Eigen::Index at = 3 * (d * nF + f) + slot;
        inner[at] = mesh.F(f, k);
        values[at] = g(d);
      }
    }
  }
  return Eigen::SparseMatrix<double>(G);
}

Eigen::SparseMatrix<double> divergenceOperator(const TriMesh& mesh) {
  const Eigen::SparseMatrix<double> G = gradientOperator(mesh);
  const Eigen::VectorXd A = faceAreas(mesh);
  Eigen::VectorXd A3(3 * A.size());
  A3 << A, A, A;
  Eigen::SparseMatrix<double> D = -(G.transpose() * A3.asDiagonal());
  D.makeCompressed();
  return D;
}

Eigen::SparseMatrix<double> laplacianSquared(const Eigen::SparseMatrix<double>& L,
                                             const Eigen::VectorXd& weight) {
  const Eigen::Index n = L.cols();
  if (L.rows() != n || weight.size() != n)
    throw InputError(fmt::format("laplacianSquared: a {}×{} matrix with {} weights", L.rows(),
                                 L.cols(), weight.size()));
  using Sparse = Eigen::SparseMatrix<double>;
  // Column j of L·W·L is Σ_k L(:, k)·w_k·L(k, j); L is symmetric, so L(:, k) is column k.
  std::vector<double> sum(static_cast<size_t>(n), 0.0);
  std::vector<Eigen::Index> seenIn(static_cast<size_t>(n), -1);  // column that last touched row i
  std::vector<int> rows;
  std::vector<int> outer(static_cast<size_t>(n) + 1, 0), inner;
  std::vector<double> values;
  inner.reserve(static_cast<size_t>(4 * L.nonZeros()));
  values.reserve(static_cast<size_t>(4 * L.nonZeros()));
  for (Eigen::Index j = 0; j < n; ++j) {
    rows.clear();
    for (Sparse::InnerIterator a(L, j); a; ++a) {
      const Eigen::Index k = a.row();
      const double wkj = weight[k] * a.value();
      for (Sparse::InnerIterator b(L, k); b; ++b) {
        const Eigen::Index i = b.row();
        if (seenIn[i] != j) {
          seenIn[i] = j;
          sum[i] = 0;
          rows.push_back(static_cast<int>(i));
        }
        sum[i] += b.value() * wkj;
      }
    }
    std::sort(rows.begin(), rows.end());
    for (int i : rows) {
      inner.push_back(i);
      values.push_back(sum[i]);
    }
    outer[j + 1] = static_cast<int>(inner.size());
  }
  return Sparse(Eigen::Map<const Sparse>(n, n, static_cast<Eigen::Index>(inner.size()),
                                         outer.data(), inner.data(), values.data()));
}

}  // namespace s2p
