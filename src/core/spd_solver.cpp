#include "core/spd_solver.h"

#include <cholmod.h>
#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "core/error.h"

namespace s2p {
namespace {

// The lower triangle (row ≥ column) of a column-major sparse matrix, as CSC arrays.
struct LowerCsc {
  int n = 0;
  std::vector<int> outer, inner;
  std::vector<double> values;
};

LowerCsc lowerTriangle(const Eigen::SparseMatrix<double>& A, const char* what) {
  if (A.rows() != A.cols())
    throw InputError(fmt::format("SpdSolver::{}: the matrix is {}×{}; it must be square", what,
                                 A.rows(), A.cols()));
  if (A.rows() == 0) throw InputError(fmt::format("SpdSolver::{}: the matrix is empty", what));
  LowerCsc L;
  L.n = static_cast<int>(A.rows());
  L.outer.assign(L.n + 1, 0);
  L.inner.reserve(A.nonZeros() / 2 + L.n);
  L.values.reserve(A.nonZeros() / 2 + L.n);
  for (int c = 0; c < L.n; ++c) {
    // InnerIterator visits rows in increasing order, also for uncompressed matrices.
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
      if (it.row() < c) continue;
      if (!std::isfinite(it.value()))
        throw InputError(
            fmt::format("SpdSolver::{}: entry ({}, {}) is {}; the matrix must be "
                        "finite",
                        what, it.row(), c, it.value()));
      L.inner.push_back(static_cast<int>(it.row()));
      L.values.push_back(it.value());
    }
    L.outer[c + 1] = static_cast<int>(L.inner.size());
  }
  return L;
}

// A non-owning CHOLMOD view of the lower triangle (stype −1: symmetric, lower part stored).
cholmod_sparse view(LowerCsc& L) {
  cholmod_sparse s{};
  s.nrow = s.ncol = static_cast<size_t>(L.n);
  s.nzmax = L.inner.size();
  s.p = L.outer.data();
  s.i = L.inner.data();
  s.x = L.values.data();
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

std::string statusText(int status) {
  switch (status) {
    case CHOLMOD_OUT_OF_MEMORY:
      return "out of memory";
    case CHOLMOD_TOO_LARGE:
      return "problem too large";
    case CHOLMOD_INVALID:
      return "invalid input";
    case CHOLMOD_NOT_INSTALLED:
      return "method not installed";
    default:
      return fmt::format("status {}", status);
  }
}

void startCommon(cholmod_common& c) {
  cholmod_start(&c);
  c.print = 0;  // errors are reported through exceptions, not stdout
  c.error_handler = nullptr;
  c.supernodal = CHOLMOD_SUPERNODAL;
}

// Calls the runtime library's `function`(value), found at run time so that the program links
// whichever BLAS and OpenMP there are, unless the user set `envVar` to choose for themselves.
void setUnlessUserDid(const char* envVar, const char* function, int value) {
  if (std::getenv(envVar) != nullptr) return;
  if (auto* set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, function))) set(value);
}

// CHOLMOD's supernodal factorisation calls BLAS on many small dense blocks. OpenBLAS's worker
// threads spin-wait between those calls: on two cores they cost more than they give (a
// segmentation spent three quarters of its time in the kernel). One BLAS thread.
void useOneBlasThread() {
  static const bool done = (setUnlessUserDid("OPENBLAS_NUM_THREADS", "openblas_set_num_threads", 1),
                            true);
  (void)done;
}

// The same for OpenMP: Debian's CHOLMOD opens a parallel region of a fixed thread count for
// every large supernode, and the wake-ups cost more than the copies they share (futex calls
// were half of a segmentation's time, 50 s against 18 s with one thread). Dynamic adjustment
// lets the runtime give the region only the cores that are idle. The setting belongs to the
// calling thread, so every thread that factors sets it once.
void useIdleOpenMpThreads() {
  thread_local const bool done = (setUnlessUserDid("OMP_DYNAMIC", "omp_set_dynamic", 1), true);
  (void)done;
}

}  // namespace

struct SpdSolver::Impl {
  Ordering ordering;
  cholmod_common common;
  cholmod_factor* factor = nullptr;  // symbolic once analysed, numeric when numericValid
  bool numericValid = false;
  int n = 0;
  std::vector<int> outer, inner;  // lower-triangle pattern of the analysed matrix

  explicit Impl(Ordering ordering) : ordering(ordering) {
    startCommon(common);
    if (ordering != Ordering::Auto) {
      common.nmethods = 1;
      common.method[0].ordering = ordering == Ordering::Amd ? CHOLMOD_AMD : CHOLMOD_METIS;
      common.postorder = 1;
    }
  }
  ~Impl() {
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  // Numeric factorisation of the analysed pattern with A's values.
  void factorize(LowerCsc& L) {
    numericValid = false;
    cholmod_sparse s = view(L);
    useIdleOpenMpThreads();
    const int ok = cholmod_factorize(&s, factor, &common);
    if (common.status == CHOLMOD_NOT_POSDEF || (ok && factor->minor < factor->n)) {
      const size_t k = factor->minor;
      const int column =
          k < factor->n && factor->Perm ? static_cast<const int*>(factor->Perm)[k] : -1;
      throw SolverError(fmt::format(
          "SpdSolver: the {}×{} matrix is not positive definite (Cholesky failed at column {}, "
          "pivot {} of the fill-reducing order); check that it is symmetric positive definite, "
          "e.g. add a mass term (M + tL), pin a vertex, or fix the Dirichlet constraints",
          n, n, column, k));
    }
    if (!ok || common.status < CHOLMOD_OK)
      throw SolverError(
          fmt::format("SpdSolver: CHOLMOD factorisation of the {}×{} matrix failed "
                      "({})",
                      n, n, statusText(common.status)));
    numericValid = true;
  }
};

SpdSolver::SpdSolver(Ordering ordering) : impl_(std::make_unique<Impl>(ordering)) {
  useOneBlasThread();
}
SpdSolver::~SpdSolver() = default;
SpdSolver::SpdSolver(SpdSolver&&) noexcept = default;
SpdSolver& SpdSolver::operator=(SpdSolver&&) noexcept = default;

void SpdSolver::compute(const Eigen::SparseMatrix<double>& A) { compute(A, 1); }

namespace {

// The lower-triangle pattern of the graph of b×b blocks of L (values 1: only the pattern is
// analysed).
LowerCsc blockPattern(const LowerCsc& L, int b) {
  LowerCsc B;
  B.n = L.n / b;
  B.outer.assign(B.n + 1, 0);
  std::vector<int> rows;
  for (int C = 0; C < B.n; ++C) {
    rows.clear();
    for (int c = C * b; c < (C + 1) * b; ++c)
      for (int k = L.outer[c]; k < L.outer[c + 1]; ++k) rows.push_back(L.inner[k] / b);
    rows.push_back(C);  // the diagonal block, even when its entries are all implicit zeros
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    for (int R : rows)
      if (R >= C) B.inner.push_back(R);
    B.outer[C + 1] = static_cast<int>(B.inner.size());
  }
  B.values.assign(B.inner.size(), 1.0);
  return B;
}

}  // namespace

void SpdSolver::compute(const Eigen::SparseMatrix<double>& A, int blockSize) {
  if (!impl_) impl_ = std::make_unique<Impl>(Ordering::Auto);  // a moved-from solver is reusable
  if (blockSize < 1 || A.rows() % blockSize != 0)
    throw InputError(fmt::format("SpdSolver::compute: a {}×{} matrix cannot be made of {}×{} blocks",
                                 A.rows(), A.cols(), blockSize, blockSize));
  LowerCsc L = lowerTriangle(A, "compute");
  Impl& s = *impl_;
  if (s.factor) cholmod_free_factor(&s.factor, &s.common);
  s.numericValid = false;
  s.n = 0;
  cholmod_sparse view_ = view(L);
  if (blockSize == 1) {
    s.factor = cholmod_analyze(&view_, &s.common);
  } else {
    // Order the blocks with the solver's method, then analyse L with that order expanded.
    LowerCsc blocks = blockPattern(L, blockSize);
    cholmod_sparse blockView = view(blocks);
    cholmod_factor* blockFactor = cholmod_analyze(&blockView, &s.common);
    if (!blockFactor || s.common.status < CHOLMOD_OK)
      throw SolverError(fmt::format("SpdSolver: CHOLMOD analysis of the {}×{} block graph failed "
                                    "({})",
                                    blocks.n, blocks.n, statusText(s.common.status)));
    std::vector<int> perm(L.n);
    const int* blockPerm = static_cast<const int*>(blockFactor->Perm);
    for (int k = 0; k < blocks.n; ++k)
      for (int r = 0; r < blockSize; ++r) perm[k * blockSize + r] = blockPerm[k] * blockSize + r;
    cholmod_free_factor(&blockFactor, &s.common);
    const int nmethods = s.common.nmethods, ordering = s.common.method[0].ordering;
    const int postorder = s.common.postorder;
    s.common.nmethods = 1;
    s.common.method[0].ordering = CHOLMOD_GIVEN;
    s.common.postorder = 1;
    s.factor = cholmod_analyze_p(&view_, perm.data(), nullptr, 0, &s.common);
    s.common.nmethods = nmethods;
    s.common.method[0].ordering = ordering;
    s.common.postorder = postorder;
  }
  if (!s.factor || s.common.status < CHOLMOD_OK)
    throw SolverError(fmt::format("SpdSolver: CHOLMOD analysis of the {}×{} matrix failed ({})",
                                  L.n, L.n, statusText(s.common.status)));
  s.n = L.n;
  s.outer = L.outer;
  s.inner = L.inner;
  s.factorize(L);
}

void SpdSolver::refactor(const Eigen::SparseMatrix<double>& A) {
  if (!impl_ || !impl_->factor)
    throw SolverError("SpdSolver::refactor: no symbolic analysis yet; call compute() first");
  LowerCsc L = lowerTriangle(A, "refactor");
  Impl& s = *impl_;
  if (L.n != s.n || L.outer != s.outer || L.inner != s.inner)
    throw SolverError(fmt::format(
        "SpdSolver::refactor: the sparsity pattern changed ({}×{} with {} lower entries, was "
        "{}×{} with {}); call compute() for a new pattern",
        L.n, L.n, L.inner.size(), s.n, s.n, s.inner.size()));
  s.factorize(L);
}

Eigen::MatrixXd SpdSolver::solve(const Eigen::MatrixXd& B) const {
  if (!ready())
    throw SolverError(
        "SpdSolver::solve: no valid factorisation; call compute() first (and make "
        "sure it succeeded)");
  const Impl& s = *impl_;
  if (B.rows() != s.n)
    throw InputError(
        fmt::format("SpdSolver::solve: right-hand side has {} rows, the matrix is "
                    "{}×{}",
                    B.rows(), s.n, s.n));
  if (B.cols() == 0) return Eigen::MatrixXd(s.n, 0);
  cholmod_dense b{};
  b.nrow = static_cast<size_t>(B.rows());
  b.ncol = static_cast<size_t>(B.cols());
  b.nzmax = b.nrow * b.ncol;
  b.d = b.nrow;
  b.x = const_cast<double*>(B.data());  // read only by cholmod_solve
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  // A private cholmod_common per call keeps concurrent const solves independent.
  cholmod_common c;
  startCommon(c);
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, s.factor, &b, &c);
  if (!x) {
    const int status = c.status;
    cholmod_finish(&c);
    throw SolverError(
        fmt::format("SpdSolver::solve: CHOLMOD solve failed ({})", statusText(status)));
  }
  Eigen::MatrixXd X =
      Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x), B.rows(), B.cols());
  cholmod_free_dense(&x, &c);
  cholmod_finish(&c);
  return X;
}

Eigen::VectorXd SpdSolver::solve(const Eigen::VectorXd& b) const {
  return solve(Eigen::MatrixXd(b)).col(0);
}

int SpdSolver::rows() const {
  return impl_ ? impl_->n : 0;
}

bool SpdSolver::ready() const {
  return impl_ && impl_->factor && impl_->numericValid;
}

}  // namespace s2p
