#include "bcassim/mechanics/solvers/CholeskyFactor.h"

#include <cholmod.h>
#include <dlfcn.h>
#include <omp.h>

#include <atomic>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "bcassim/Error.h"

namespace bcassim {
namespace {

// A cholmod_common set up for bcassim: supernodal LL^T, quiet (the library never prints), CPU
// only. Every object that calls CHOLMOD owns one, because CHOLMOD keeps workspace and status
// there and is thread-safe only across distinct cholmod_common objects.
struct Common {
  cholmod_common c;
  Common() {
    cholmod_start(&c);
    c.print = 0;
    c.supernodal = CHOLMOD_SUPERNODAL;
    c.useGPU = 0;
  }
  ~Common() { cholmod_finish(&c); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
};

// Throws for a CHOLMOD call that failed; where names the operation.
void check(int ok, const cholmod_common& c, const char* where) {
  if (ok && c.status >= CHOLMOD_OK) return;
  if (c.status == CHOLMOD_OUT_OF_MEMORY) throw std::bad_alloc();
  throw NumericalError(std::string(where) + " failed (CHOLMOD status " + std::to_string(c.status) +
                       ")");
}

// CHOLMOD view of A without copying; stype = -1 reads the lower triangle only.
cholmod_sparse sparseView(const SparseMatrix& A) {
  cholmod_sparse v{};
  v.nrow = static_cast<size_t>(A.rows());
  v.ncol = static_cast<size_t>(A.cols());
  v.nzmax = static_cast<size_t>(A.nonZeros());
  v.p = const_cast<int*>(A.outerIndexPtr());
  v.i = const_cast<int*>(A.innerIndexPtr());
  v.nz = A.isCompressed() ? nullptr : const_cast<int*>(A.innerNonZeroPtr());
  v.x = const_cast<double*>(A.valuePtr());
  v.stype = -1;
  v.itype = CHOLMOD_INT;
  v.xtype = CHOLMOD_REAL;
  v.dtype = CHOLMOD_DOUBLE;
  v.sorted = 1;
  v.packed = A.isCompressed() ? 1 : 0;
  return v;
}

// CHOLMOD view of a column-major block; CHOLMOD only reads a right-hand side.
cholmod_dense denseView(const double* data, Eigen::Index rows, Eigen::Index cols) {
  cholmod_dense v{};
  v.nrow = static_cast<size_t>(rows);
  v.ncol = static_cast<size_t>(cols);
  v.d = static_cast<size_t>(rows);
  v.nzmax = static_cast<size_t>(rows * cols);
  v.x = const_cast<double*>(data);
  v.xtype = CHOLMOD_REAL;
  v.dtype = CHOLMOD_DOUBLE;
  return v;
}

}  // namespace

struct CholeskyFactor::Symbolic {
  Common common;
  cholmod_factor* L = nullptr;  // supernodal, pattern only; copied by every Numeric
  Eigen::Index rows = 0;
  Eigen::Index matrixNonZeros = 0;
  std::int64_t factorNonZeros = 0;
  ~Symbolic() { cholmod_free_factor(&L, &common.c); }
};

// The values of a supernodal L rounded to float, made by the first single-precision solve.
struct SingleCopy {
  std::once_flag made;
  std::vector<float> x;
};

struct CholeskyFactor::Numeric {
  Common common;
  cholmod_factor* L = nullptr;  // numerical factor, valid when factorized
  bool factorized = false;
  std::unique_ptr<SingleCopy> single = std::make_unique<SingleCopy>();
  void release() {
    cholmod_free_factor(&L, &common.c);
    factorized = false;
    single = std::make_unique<SingleCopy>();
  }
  ~Numeric() { release(); }
};

struct CholeskyFactor::Workspace::Impl {
  Common common;
  cholmod_dense* X = nullptr;  // solution, copied out to Eigen
  cholmod_dense* Y = nullptr;  // permuted right-hand sides
  cholmod_dense* E = nullptr;  // supernodal solve scratch
  cholmod_sparse* Xset = nullptr;
  Eigen::VectorXf yf, tf;  // single-precision sweep: permuted vector, off-diagonal products
  Eigen::VectorXd yd, td;  // the same in double
  ~Impl() {
    cholmod_free_dense(&X, &common.c);
    cholmod_free_dense(&Y, &common.c);
    cholmod_free_dense(&E, &common.c);
    cholmod_free_sparse(&Xset, &common.c);
  }
};

CholeskyFactor::Workspace::Workspace() : impl_(std::make_unique<Impl>()) {}
CholeskyFactor::Workspace::~Workspace() = default;
CholeskyFactor::Workspace::Workspace(Workspace&&) noexcept = default;
CholeskyFactor::Workspace& CholeskyFactor::Workspace::operator=(Workspace&&) noexcept = default;

CholeskyFactor::CholeskyFactor() : numeric_(std::make_unique<Numeric>()) {}
CholeskyFactor::~CholeskyFactor() = default;

// Debian's CHOLMOD asks for 4 OpenMP threads in its supernodal kernels whatever OMP_NUM_THREADS
// says; on 2 cores, and inside parallel sigma-point threads, that oversubscribes (2-4x slower).
// Dynamic teams (a per-thread setting) let the runtime shrink them to the cores that are free.
// When the BLAS behind CHOLMOD is OpenBLAS (the pthread build: the serial build is not safe for
// concurrent calls from our sigma-point threads), keep each call on its calling thread.
static void limitCholmodThreads() {
  omp_set_dynamic(1);
  static const bool blasLimited = [] {
    using SetThreads = void (*)(int);
    if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
      set(1);
    return true;
  }();
  (void)blasLimited;
}

void CholeskyFactor::analyzePattern(const SparseMatrix& A) {
  if (A.rows() != A.cols()) throw std::invalid_argument("CholeskyFactor: matrix is not square");
  numeric_->release();
  auto symbolic = std::make_shared<Symbolic>();
  cholmod_sparse view = sparseView(A);
  symbolic->L = cholmod_analyze(&view, &symbolic->common.c);
  check(symbolic->L != nullptr, symbolic->common.c, "Cholesky analysis");
  symbolic->rows = A.rows();
  symbolic->matrixNonZeros = A.nonZeros();
  symbolic->factorNonZeros = static_cast<std::int64_t>(symbolic->common.c.lnz);
  cholmod_free_work(&symbolic->common.c);  // the analysis is kept for its lifetime; its scratch not
  symbolic_ = std::move(symbolic);
}

void CholeskyFactor::factorize(const SparseMatrix& A) {
  if (!matchesPattern(A)) analyzePattern(A);
  Numeric& num = *numeric_;
  num.factorized = false;
  num.single = std::make_unique<SingleCopy>();
  if (num.L == nullptr) {
    num.L = cholmod_copy_factor(symbolic_->L, &num.common.c);
    check(num.L != nullptr, num.common.c, "Cholesky factor allocation");
  }
  limitCholmodThreads();
  cholmod_sparse view = sparseView(A);
  const int ok = cholmod_factorize(&view, num.L, &num.common.c);
  if (num.common.c.status == CHOLMOD_NOT_POSDEF || (ok && num.L->minor < num.L->n)) {
    const auto column = num.L->minor;
    num.release();  // a failed factor is rebuilt from the analysis next time
    throw NumericalError("Cholesky factorisation: matrix is not positive definite (pivot " +
                         std::to_string(column) + " of " + std::to_string(A.rows()) + ")");
  }
  if (!ok || num.common.c.status < CHOLMOD_OK) num.release();
  check(ok, num.common.c, "Cholesky factorisation");
  num.factorized = true;
}

std::shared_ptr<CholeskyFactor> CholeskyFactor::cloneAnalysis() const {
  if (!symbolic_) throw std::logic_error("CholeskyFactor::cloneAnalysis before analyzePattern");
  auto clone = std::make_shared<CholeskyFactor>();
  clone->symbolic_ = symbolic_;
  return clone;
}

void CholeskyFactor::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X, Workspace& work) const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor::solve before a factorisation");
  if (B.rows() != rows()) throw std::invalid_argument("CholeskyFactor::solve: wrong size of b");
  X.resize(B.rows(), B.cols());
  if (B.cols() == 0) return;
  Workspace::Impl& w = *work.impl_;
  cholmod_dense b = denseView(B.data(), B.rows(), B.cols());
  limitCholmodThreads();
  // Without a Bset, cholmod_solve2 on a supernodal factor only reads L and writes the
  // workspace's buffers and cholmod_common: this is what makes concurrent solves safe.
  const int ok =
      cholmod_solve2(CHOLMOD_A, numeric_->L, &b, nullptr, &w.X, &w.Xset, &w.Y, &w.E, &w.common.c);
  check(ok, w.common.c, "Cholesky solve");
  X = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>(
      static_cast<const double*>(w.X->x), B.rows(), B.cols(),
      Eigen::OuterStride<>(static_cast<Eigen::Index>(w.X->d)));
}

void CholeskyFactor::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const {
  Workspace work;
  solve(B, X, work);
}

void CholeskyFactor::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, Workspace& work) const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor::solve before a factorisation");
  if (b.size() != rows()) throw std::invalid_argument("CholeskyFactor::solve: wrong size of b");
  Workspace::Impl& w = *work.impl_;
  cholmod_dense bView = denseView(b.data(), b.size(), 1);
  const int ok = cholmod_solve2(CHOLMOD_A, numeric_->L, &bView, nullptr, &w.X, &w.Xset, &w.Y, &w.E,
                                &w.common.c);
  check(ok, w.common.c, "Cholesky solve");
  x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(w.X->x), b.size());
}

void CholeskyFactor::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  Workspace work;
  solve(b, x, work);
}

namespace {

// x = P^T L^{-T} L^{-1} P b over the supernodes of L (CHOLMOD's layout: supernode k holds columns
// super[k]..super[k+1]-1 as a column-major block of nsrow rows, whose first nscol row indices are
// those columns), with the values Lx in the working precision of y and t.
template <typename Scalar>
void supernodalSolve(const cholmod_factor& L, const Scalar* Lx, const Eigen::VectorXd& b,
                     Eigen::VectorXd& x, Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& y,
                     Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& t) {
  using Block = Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>, 0,
                           Eigen::OuterStride<>>;
  const auto n = static_cast<Eigen::Index>(L.n);
  const auto nsuper = static_cast<int>(L.nsuper);
  const int* super = static_cast<const int*>(L.super);
  const int* pi = static_cast<const int*>(L.pi);
  const int* px = static_cast<const int*>(L.px);
  const int* rows = static_cast<const int*>(L.s);
  const int* perm = static_cast<const int*>(L.Perm);
  y.resize(n);
  t.resize(static_cast<Eigen::Index>(L.maxesize));
  for (Eigen::Index i = 0; i < n; ++i) y[i] = static_cast<Scalar>(b[perm[i]]);

  for (int k = 0; k < nsuper; ++k) {  // L y = P b
    const int first = super[k], nscol = super[k + 1] - first;
    const int nsrow = pi[k + 1] - pi[k], below = nsrow - nscol;
    const Block block(Lx + px[k], nsrow, nscol, Eigen::OuterStride<>(nsrow));
    auto yk = y.segment(first, nscol);
    block.topRows(nscol).template triangularView<Eigen::Lower>().solveInPlace(yk);
    if (below == 0) continue;
    auto tk = t.head(below);
    tk.noalias() = block.bottomRows(below) * yk;
    const int* r = rows + pi[k] + nscol;
    for (int i = 0; i < below; ++i) y[r[i]] -= tk[i];
  }
  for (int k = nsuper - 1; k >= 0; --k) {  // L^T y = y
    const int first = super[k], nscol = super[k + 1] - first;
    const int nsrow = pi[k + 1] - pi[k], below = nsrow - nscol;
    const Block block(Lx + px[k], nsrow, nscol, Eigen::OuterStride<>(nsrow));
    auto yk = y.segment(first, nscol);
    if (below > 0) {
      auto tk = t.head(below);
      const int* r = rows + pi[k] + nscol;
      for (int i = 0; i < below; ++i) tk[i] = y[r[i]];
      yk.noalias() -= block.bottomRows(below).transpose() * tk;
    }
    block.topRows(nscol).template triangularView<Eigen::Lower>().transpose().solveInPlace(yk);
  }
  x.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) x[perm[i]] = static_cast<double>(y[i]);
}

}  // namespace

void CholeskyFactor::solveSinglePrecision(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                          Workspace& work) const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor::solve before a factorisation");
  if (b.size() != rows()) throw std::invalid_argument("CholeskyFactor::solve: wrong size of b");
  prepareSinglePrecision();
  Workspace::Impl& w = *work.impl_;
  supernodalSolve(*numeric_->L, numeric_->single->x.data(), b, x, w.yf, w.tf);
}

void CholeskyFactor::prepareSinglePrecision() const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor: no factorisation to round");
  const cholmod_factor& L = *numeric_->L;
  SingleCopy& single = *numeric_->single;
  std::call_once(single.made, [&] {
    const double* Lx = static_cast<const double*>(L.x);
    single.x.assign(Lx, Lx + L.xsize);
  });
}

void CholeskyFactor::solveSupernodalDouble(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                           Workspace& work) const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor::solve before a factorisation");
  if (b.size() != rows()) throw std::invalid_argument("CholeskyFactor::solve: wrong size of b");
  Workspace::Impl& w = *work.impl_;
  supernodalSolve(*numeric_->L, static_cast<const double*>(numeric_->L->x), b, x, w.yd, w.td);
}

bool CholeskyFactor::isAnalyzed() const { return symbolic_ != nullptr; }
bool CholeskyFactor::isFactorized() const { return numeric_->factorized; }
Eigen::Index CholeskyFactor::rows() const { return symbolic_ ? symbolic_->rows : 0; }

bool CholeskyFactor::matchesPattern(const SparseMatrix& A) const {
  return symbolic_ && A.rows() == symbolic_->rows && A.cols() == symbolic_->rows &&
         A.nonZeros() == symbolic_->matrixNonZeros;
}

std::int64_t CholeskyFactor::factorNonZeros() const {
  return symbolic_ ? symbolic_->factorNonZeros : 0;
}

void factorizeUnshared(std::shared_ptr<CholeskyFactor>& factor, const SparseMatrix& A) {
  if (!factor) {
    factor = std::make_shared<CholeskyFactor>();
  } else if (factor.use_count() > 1) {
    factor = factor->isAnalyzed() && factor->matchesPattern(A) ? factor->cloneAnalysis()
                                                               : std::make_shared<CholeskyFactor>();
  } else {
    // use_count() is a relaxed load; the fence orders our writes after the last reads of the
    // owners who released the factor.
    std::atomic_thread_fence(std::memory_order_acquire);
  }
  factor->factorize(A);
}

}  // namespace bcassim
