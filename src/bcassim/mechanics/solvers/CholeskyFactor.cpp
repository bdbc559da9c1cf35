#include "bcassim/mechanics/solvers/CholeskyFactor.h"

#include <cholmod.h>
#include <dlfcn.h>
#include <omp.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/mechanics/ArenaLoop.h"
#include "bcassim/mechanics/solvers/SupernodalCholesky.h"

namespace bcassim {

// A cholmod_common set up for bcassim: supernodal LL^T, quiet (the library never prints), CPU
// only. Every object that calls CHOLMOD owns one, because CHOLMOD keeps workspace and status
// there and is thread-safe only across distinct cholmod_common objects. (Outside the anonymous
// namespace, as SubtreeSplit and SplitScratch: the header's classes hold them.)
struct CholmodCommon {
  cholmod_common c;
  CholmodCommon() {
    cholmod_start(&c);
    c.print = 0;
    c.supernodal = CHOLMOD_SUPERNODAL;
    c.useGPU = 0;
  }
  ~CholmodCommon() { cholmod_finish(&c); }
  CholmodCommon(const CholmodCommon&) = delete;
  CholmodCommon& operator=(const CholmodCommon&) = delete;
};

namespace {

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

namespace {

// The supernodes of a CHOLMOD supernodal factor (supernode k holds columns super[k]..super[k+1]-1
// as a column-major block of nsrow rows, whose first nscol row indices are those columns) with its
// values Lx in the working precision Scalar, and the two sweeps' work on one supernode.
template <typename Scalar>
struct Supernodes {
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  using Block = Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>, 0,
                           Eigen::OuterStride<>>;
  const Scalar* Lx;
  const int* super;
  const int* pi;
  const int* px;
  const int* rows;

  Supernodes(const cholmod_factor& L, const Scalar* values)
      : Lx(values),
        super(static_cast<const int*>(L.super)),
        pi(static_cast<const int*>(L.pi)),
        px(static_cast<const int*>(L.px)),
        rows(static_cast<const int*>(L.s)) {}

  // Supernode k: its columns first..first+nscol-1, its block (diagonal block on top of `below`
  // rows), and the row indices of those.
  struct Panel {
    int first, nscol, below;
    Block block;
    const int* rows;
    auto lower() const { return block.bottomRows(below); }
  };
  Panel panel(int k) const {
    const int first = super[k], nscol = super[k + 1] - first;
    const int nsrow = pi[k + 1] - pi[k];
    return {first, nscol, nsrow - nscol,
            Block(Lx + px[k], nsrow, nscol, Eigen::OuterStride<>(nsrow)), rows + pi[k] + nscol};
  }

  // y_k = L_kk^-1 y_k, t = L_bk y_k by product(L_bk, y_k, t), then update(row, t_i) for each row
  // below (y[row] -= t_i where this sweep owns the row).
  template <class Product, class Update>
  void forward(int k, Vector& y, Vector& t, Product&& product, Update&& update) const {
    const Panel p = panel(k);
    auto yk = y.segment(p.first, p.nscol);
    p.block.topRows(p.nscol).template triangularView<Eigen::Lower>().solveInPlace(yk);
    if (p.below == 0) return;
    product(p.lower(), yk, t.head(p.below));
    for (int i = 0; i < p.below; ++i) update(p.rows[i], t[i]);
  }

  // y_k = L_kk^-T (y_k - L_bk^T y_b), b the rows below (solved before: they are ancestors), the
  // product by product(L_bk, y_b, y_k).
  template <class Product>
  void backward(int k, Vector& y, Vector& t, Product&& product) const {
    const Panel p = panel(k);
    auto yk = y.segment(p.first, p.nscol);
    if (p.below > 0) {
      for (int i = 0; i < p.below; ++i) t[i] = y[p.rows[i]];
      product(p.lower(), t.head(p.below), yk);
    }
    p.block.topRows(p.nscol).template triangularView<Eigen::Lower>().transpose().solveInPlace(yk);
  }

  // The products whole, or cut into kProductChunks pieces for each(piece) to run, concurrently or
  // not (the same arithmetic either way): rows of t = L_bk y_k, columns of y_k -= L_bk^T y_b.
  static constexpr int kProductChunks = 4;
  static constexpr long kChunkedEntries = 1L << 16;
  bool chunked(int k) const {
    const long nscol = super[k + 1] - super[k], below = pi[k + 1] - pi[k] - nscol;
    return below * nscol >= kChunkedEntries;
  }
  static std::pair<int, int> piece(int c, Eigen::Index size) {
    const auto lo = static_cast<int>(size * c / kProductChunks);
    return {lo, static_cast<int>(size * (c + 1) / kProductChunks) - lo};
  }
  static constexpr auto wholeForward = [](const auto& lower, const auto& yk, auto tk) {
    tk.noalias() = lower * yk;
  };
  static constexpr auto wholeBackward = [](const auto& lower, const auto& tk, auto yk) {
    yk.noalias() -= lower.transpose() * tk;
  };
  template <class Each>
  static auto piecewiseForward(Each& each) {
    return [&each](const auto& lower, const auto& yk, auto tk) {
      each([&](int c) {
        const auto [lo, len] = piece(c, lower.rows());
        tk.segment(lo, len).noalias() = lower.middleRows(lo, len) * yk;
      });
    };
  }
  template <class Each>
  static auto piecewiseBackward(Each& each) {
    return [&each](const auto& lower, const auto& tk, auto yk) {
      each([&](int c) {
        const auto [lo, len] = piece(c, lower.cols());
        yk.segment(lo, len).noalias() -= lower.middleCols(lo, len).transpose() * tk;
      });
    };
  }
};

// Leaves the forward sweep's result as it is (a solve without a correction between the sweeps).
struct NoMidCorrection {
  template <class Vector>
  void operator()(Vector& /*y*/) const {}
};

// x = P^T L^{-T} mid(L^{-1} P b), one supernode after the other; mid(y) may change y in place.
template <typename Scalar, class Mid = NoMidCorrection>
void supernodalSolve(const cholmod_factor& L, const Scalar* Lx, const Eigen::VectorXd& b,
                     Eigen::VectorXd& x, Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& y,
                     Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& t, Mid&& mid = {}) {
  const Supernodes<Scalar> sn(L, Lx);
  const auto n = static_cast<Eigen::Index>(L.n);
  const auto nsuper = static_cast<int>(L.nsuper);
  const int* perm = static_cast<const int*>(L.Perm);
  y.resize(n);
  t.resize(static_cast<Eigen::Index>(L.maxesize));
  for (Eigen::Index i = 0; i < n; ++i) y[i] = static_cast<Scalar>(b[perm[i]]);
  const auto own = [&](int r, Scalar v) { y[r] -= v; };
  for (int k = 0; k < nsuper; ++k) sn.forward(k, y, t, sn.wholeForward, own);
  mid(y);
  for (int k = nsuper - 1; k >= 0; --k) sn.backward(k, y, t, sn.wholeBackward);
  x.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) x[perm[i]] = static_cast<double>(y[i]);
}

// The supernodes of L in kSplitGroups groups of whole subtrees of the supernodal elimination tree,
// which a sweep may run concurrently, and the `top` supernodes above them (every ancestor of a
// group's supernode is in its subtree or in top), which run alone. The groups do not depend on the
// number of threads, so neither does the result.
constexpr int kSplitGroups = 4;

}  // namespace

struct SubtreeSplit {
  std::vector<std::vector<int>> groups;  // each ascending
  std::vector<int> top;                  // ascending
  std::vector<int> topRows;              // the columns of the top supernodes
  std::vector<int> slot;                 // slot[row]: index into topRows, or -1
};

namespace {

// Splits the tree greedily: the heaviest subtree (by factor entries, the sweeps' work) gives its
// root to the top and its children to the candidates, until the heaviest is within 10 % of an
// equal share or the top holds 32 supernodes; the subtrees then go to the lightest group,
// heaviest first.
SubtreeSplit splitSupernodes(const cholmod_factor& L) {
  const auto nsuper = static_cast<int>(L.nsuper);
  const int* super = static_cast<const int*>(L.super);
  const int* pi = static_cast<const int*>(L.pi);
  const int* rows = static_cast<const int*>(L.s);
  std::vector<int> superOf(L.n), parent(static_cast<size_t>(nsuper), -1);
  std::vector<double> weight(static_cast<size_t>(nsuper)), subtree(static_cast<size_t>(nsuper));
  std::vector<std::vector<int>> children(static_cast<size_t>(nsuper));
  for (int k = 0; k < nsuper; ++k)
    for (int c = super[k]; c < super[k + 1]; ++c) superOf[static_cast<size_t>(c)] = k;
  std::vector<int> candidates;
  double total = 0;
  for (int k = 0; k < nsuper; ++k) {
    const int nscol = super[k + 1] - super[k], nsrow = pi[k + 1] - pi[k];
    const auto kk = static_cast<size_t>(k);
    weight[kk] = static_cast<double>(nsrow) * nscol;
    subtree[kk] += weight[kk];  // children (lower numbers) have added theirs
    total += weight[kk];
    if (nsrow > nscol) {
      // The lowest row below the diagonal block is in the parent: ancestors have higher columns.
      const int lowest = *std::min_element(rows + pi[k] + nscol, rows + pi[k + 1]);
      parent[kk] = superOf[static_cast<size_t>(lowest)];
      subtree[static_cast<size_t>(parent[kk])] += subtree[kk];
      children[static_cast<size_t>(parent[kk])].push_back(k);
    } else {
      candidates.push_back(k);
    }
  }
  SubtreeSplit split;
  double topWeight = 0;
  for (;;) {
    const auto heaviest = std::max_element(candidates.begin(), candidates.end(), [&](int a, int b) {
      return subtree[static_cast<size_t>(a)] < subtree[static_cast<size_t>(b)];
    });
    if (heaviest == candidates.end()) break;
    const int h = *heaviest;
    const auto hh = static_cast<size_t>(h);
    if (subtree[hh] <= 1.1 * (total - topWeight) / kSplitGroups || split.top.size() >= 32) break;
    split.top.push_back(h);
    topWeight += weight[hh];
    candidates.erase(heaviest);
    candidates.insert(candidates.end(), children[hh].begin(), children[hh].end());
  }
  std::sort(candidates.begin(), candidates.end(), [&](int a, int b) {
    return subtree[static_cast<size_t>(a)] > subtree[static_cast<size_t>(b)] ||
           (subtree[static_cast<size_t>(a)] == subtree[static_cast<size_t>(b)] && a < b);
  });
  std::vector<double> load(kSplitGroups, 0.0);
  std::vector<int> groupOf(static_cast<size_t>(nsuper), -1);
  for (int c : candidates) {
    const auto g = std::min_element(load.begin(), load.end()) - load.begin();
    load[static_cast<size_t>(g)] += subtree[static_cast<size_t>(c)];
    groupOf[static_cast<size_t>(c)] = static_cast<int>(g);
  }
  for (int k : split.top) groupOf[static_cast<size_t>(k)] = kSplitGroups;
  // A supernode outside the top belongs to the group of its first ancestor that has one.
  split.groups.resize(kSplitGroups);
  for (int k = nsuper - 1; k >= 0; --k) {
    const auto kk = static_cast<size_t>(k);
    if (groupOf[kk] < 0) groupOf[kk] = groupOf[static_cast<size_t>(parent[kk])];
  }
  for (int k = 0; k < nsuper; ++k) {
    const int g = groupOf[static_cast<size_t>(k)];
    if (g < kSplitGroups) split.groups[static_cast<size_t>(g)].push_back(k);
  }
  std::sort(split.top.begin(), split.top.end());
  split.slot.assign(L.n, -1);
  for (int k : split.top)
    for (int c = super[k]; c < super[k + 1]; ++c) {
      split.slot[static_cast<size_t>(c)] = static_cast<int>(split.topRows.size());
      split.topRows.push_back(c);
    }
  return split;
}

}  // namespace

// Per-group scratch of a split solve in precision Scalar. Outside the anonymous namespace, as
// SubtreeSplit: Workspace::Impl holds them.
template <typename Scalar>
struct SplitScratch {
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  std::vector<Vector> t, delta;  // per group: products; what the group takes from the top rows
};

namespace {

// supernodalSolve with the groups of `split` on `arena`'s threads: the forward sweep runs the
// groups concurrently, each collecting what it takes from the top rows in its own delta, then the
// deltas in group order, then the top; the backward sweep runs the top, then the groups (they only
// read the top rows). Any number of threads gives the same bits. mid(y) runs between the sweeps.
template <typename Scalar, class Mid = NoMidCorrection>
void splitSupernodalSolve(const cholmod_factor& L, const Scalar* Lx, const SubtreeSplit& split,
                          tbb::task_arena& arena, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                          Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& y,
                          Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& t,
                          SplitScratch<Scalar>& scratch, Mid&& mid = {}) {
  const Supernodes<Scalar> sn(L, Lx);
  const auto n = static_cast<Eigen::Index>(L.n);
  const int* perm = static_cast<const int*>(L.Perm);
  const auto topSize = static_cast<Eigen::Index>(split.topRows.size());
  y.resize(n);
  t.resize(static_cast<Eigen::Index>(L.maxesize));
  scratch.t.resize(kSplitGroups);
  scratch.delta.resize(kSplitGroups);
  for (int g = 0; g < kSplitGroups; ++g) {
    scratch.t[static_cast<size_t>(g)].resize(static_cast<Eigen::Index>(L.maxesize));
    scratch.delta[static_cast<size_t>(g)].setZero(topSize);
  }
  for (Eigen::Index i = 0; i < n; ++i) y[i] = static_cast<Scalar>(b[perm[i]]);
  const int* slot = split.slot.data();
  const auto eachPiece = [&](auto&& work) {
    forEachOnArena(arena, Supernodes<Scalar>::kProductChunks, work);
  };
  const auto own = [&](int r, Scalar v) { y[r] -= v; };
  forEachOnArena(arena, kSplitGroups, [&](int g) {
    auto& tg = scratch.t[static_cast<size_t>(g)];
    auto& delta = scratch.delta[static_cast<size_t>(g)];
    for (int k : split.groups[static_cast<size_t>(g)])
      sn.forward(k, y, tg, sn.wholeForward, [&](int r, Scalar v) {
        if (const int s = slot[r]; s >= 0)
          delta[s] += v;
        else
          y[r] -= v;
      });
  });
  for (int g = 0; g < kSplitGroups; ++g)
    for (Eigen::Index s = 0; s < topSize; ++s)
      y[split.topRows[static_cast<size_t>(s)]] -= scratch.delta[static_cast<size_t>(g)][s];
  for (int k : split.top) {
    if (sn.chunked(k))
      sn.forward(k, y, t, sn.piecewiseForward(eachPiece), own);
    else
      sn.forward(k, y, t, sn.wholeForward, own);
  }
  mid(y);
  for (auto k = split.top.rbegin(); k != split.top.rend(); ++k) {
    if (sn.chunked(*k))
      sn.backward(*k, y, t, sn.piecewiseBackward(eachPiece));
    else
      sn.backward(*k, y, t, sn.wholeBackward);
  }
  forEachOnArena(arena, kSplitGroups, [&](int g) {
    auto& tg = scratch.t[static_cast<size_t>(g)];
    const std::vector<int>& group = split.groups[static_cast<size_t>(g)];
    for (auto k = group.rbegin(); k != group.rend(); ++k) sn.backward(*k, y, tg, sn.wholeBackward);
  });
  x.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) x[perm[i]] = static_cast<double>(y[i]);
}

}  // namespace

struct CholeskyFactor::Symbolic {
  CholmodCommon common;
  cholmod_factor* L = nullptr;  // supernodal, pattern only; copied by every Numeric
  Eigen::Index rows = 0;
  Eigen::Index matrixNonZeros = 0;
  std::int64_t factorNonZeros = 0;
  // The supernodes' split for solves on several threads, made by the first such solve.
  mutable std::once_flag splitMade;
  mutable std::unique_ptr<SubtreeSplit> split;
  // The threaded numeric factorisation's plan, made by its first use for the pattern it met.
  mutable std::once_flag planMade;
  mutable std::unique_ptr<SupernodalCholesky> plan;
  // Value arrays (L's xsize doubles) of released factors of this analysis, for the next ones: a
  // build thread's 10-25 MB blocks, freed and allocated again, came back as fresh pages from
  // glibc's thread arenas (45 k more page faults in a mestdagh run, builds twice as long;
  // docs/benchmarks.md §6).
  // Their float copies (SingleCopy) likewise: a tangent built within a frame made its copy in
  // fresh pages, ~25 ms of page faults in the mestdagh liver's first frame.
  static constexpr size_t kSpareValues = 4;
  mutable std::mutex spareMutex;
  mutable std::vector<std::unique_ptr<double[]>> spareValues;
  mutable std::vector<std::unique_ptr<float[]>> spareSingles;
  std::unique_ptr<double[]> takeValues() const {
    if (std::unique_ptr<double[]> values = takeSpare(spareValues)) return values;
    return std::make_unique<double[]>(L->xsize);
  }
  void giveBack(std::unique_ptr<double[]> values) const {
    keepSpare(spareValues, std::move(values));
  }
  // L's xsize floats, to be overwritten.
  std::unique_ptr<float[]> takeSingle() const {
    if (std::unique_ptr<float[]> single = takeSpare(spareSingles)) return single;
    return std::make_unique_for_overwrite<float[]>(L->xsize);
  }
  void giveBack(std::unique_ptr<float[]> single) const {
    keepSpare(spareSingles, std::move(single));
  }
  template <class T>
  std::unique_ptr<T[]> takeSpare(std::vector<std::unique_ptr<T[]>>& spares) const {
    const std::lock_guard<std::mutex> lock(spareMutex);
    if (spares.empty()) return nullptr;
    std::unique_ptr<T[]> spare = std::move(spares.back());
    spares.pop_back();
    return spare;
  }
  template <class T>
  void keepSpare(std::vector<std::unique_ptr<T[]>>& spares, std::unique_ptr<T[]> array) const {
    const std::lock_guard<std::mutex> lock(spareMutex);
    if (spares.size() < kSpareValues) spares.push_back(std::move(array));
  }
  ~Symbolic() { cholmod_free_factor(&L, &common.c); }
};

// The values of a supernodal L rounded to float, made by the first single-precision solve, in an
// array of the analysis' spares (given back when the copy goes).
struct CholeskyFactor::SingleCopy {
  std::once_flag made;
  std::unique_ptr<float[]> x;
  std::shared_ptr<const Symbolic> from;  // where x goes back
  SingleCopy() = default;
  SingleCopy(const SingleCopy&) = delete;
  SingleCopy& operator=(const SingleCopy&) = delete;
  ~SingleCopy() {
    if (x && from) from->giveBack(std::move(x));
  }
};

struct CholeskyFactor::Numeric {
  CholmodCommon common;
  cholmod_factor* L = nullptr;  // numerical factor, valid when factorized
  bool factorized = false;
  std::unique_ptr<SingleCopy> single = std::make_unique<SingleCopy>();
  std::unique_ptr<tbb::task_arena> arena;  // factorize(A, threads)'s
  // L's values when factorize() attached them from the analysis' spares (else CHOLMOD owns them).
  std::unique_ptr<double[]> values;
  std::shared_ptr<const Symbolic> valuesFrom;
  void release() {
    if (values && L != nullptr) {
      L->x = nullptr;  // not CHOLMOD's to free
      L->xtype = CHOLMOD_PATTERN;
      valuesFrom->giveBack(std::move(values));
      valuesFrom.reset();
    }
    cholmod_free_factor(&L, &common.c);
    factorized = false;
    single = std::make_unique<SingleCopy>();
  }
  ~Numeric() { release(); }
};

struct CholeskyFactor::Workspace::Impl {
  CholmodCommon common;
  cholmod_dense* X = nullptr;  // solution, copied out to Eigen
  cholmod_dense* Y = nullptr;  // permuted right-hand sides
  cholmod_dense* E = nullptr;  // supernodal solve scratch
  cholmod_sparse* Xset = nullptr;
  Eigen::VectorXf yf, tf;  // single-precision sweep: permuted vector, off-diagonal products
  Eigen::VectorXd yd, td;  // the same in double
  Eigen::VectorXd cd;      // solveWithMidCorrection in single precision: the forward result widened
  int threads = 0;         // setThreads
  std::unique_ptr<tbb::task_arena> arena;
  SplitScratch<float> splitF;
  SplitScratch<double> splitD;
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
  // AMD, METIS and CHOLMOD's nested dissection, the best kept (CHOLMOD's default tries METIS only
  // where AMD's fill looks high, and kept AMD on the phantom's estimation liver): there nested
  // dissection has 15 % fewer entries in L and 33 % fewer flops than AMD, for 25 ms more
  // analysis once per pattern (docs/benchmarks.md §4).
  symbolic->common.c.nmethods = 4;  // method[0], a given ordering, is skipped: none is given
  symbolic->L = cholmod_analyze(&view, &symbolic->common.c);
  check(symbolic->L != nullptr, symbolic->common.c, "Cholesky analysis");
  symbolic->rows = A.rows();
  symbolic->matrixNonZeros = A.nonZeros();
  symbolic->factorNonZeros = static_cast<std::int64_t>(symbolic->common.c.lnz);
  cholmod_free_work(&symbolic->common.c);  // the analysis is kept for its lifetime; its scratch not
  symbolic_ = std::move(symbolic);
}

void CholeskyFactor::factorizeWithCholmod(const SparseMatrix& A) {
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

void CholeskyFactor::factorize(const SparseMatrix& A, int threads) {
  threads = std::max(threads, 1);
  if (!matchesPattern(A)) analyzePattern(A);
  const Symbolic& symbolic = *symbolic_;
  std::call_once(symbolic.planMade, [&] {
    const SubtreeSplit& split = subtreeSplit();
    try {
      symbolic.plan = std::make_unique<SupernodalCholesky>(*symbolic.L, A, split.groups, split.top);
    } catch (const std::invalid_argument&) {
      // A pattern the plan cannot take (a factor that is not supernodal with sorted rows, an
      // entry outside the analysis): CHOLMOD's factorisation serves.
    }
  });
  if (!symbolic.plan || !symbolic.plan->matches(A)) return factorizeWithCholmod(A);
  Numeric& num = *numeric_;
  num.factorized = false;
  num.single = std::make_unique<SingleCopy>();
  if (num.L == nullptr) {
    num.L = cholmod_copy_factor(symbolic.L, &num.common.c);
    check(num.L != nullptr, num.common.c, "Cholesky factor allocation");
  }
  if (num.L->xtype == CHOLMOD_PATTERN) {
    // The supernodal LL^T values that the plan writes, from the analysis' spares: a symbolic
    // supernodal factor becomes a numeric one by its values alone (cholmod_change_factor sets
    // only x and xtype).
    num.values = symbolic.takeValues();
    num.valuesFrom = symbolic_;
    num.L->x = num.values.get();
    num.L->xtype = CHOLMOD_REAL;
  }
  limitCholmodThreads();
  if (!num.arena || num.arena->max_concurrency() != threads)
    num.arena = std::make_unique<tbb::task_arena>(threads);
  const std::int64_t column =
      symbolic.plan->factorize(A, static_cast<double*>(num.L->x), *num.arena);
  if (column >= 0) {
    num.release();
    throw NumericalError("Cholesky factorisation: matrix is not positive definite (pivot " +
                         std::to_string(column) + " of " + std::to_string(A.rows()) + ")");
  }
  num.L->minor = num.L->n;
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

void CholeskyFactor::Workspace::setThreads(int threads) {
  if (threads < 0) throw std::invalid_argument("CholeskyFactor::Workspace: threads must be >= 0");
  impl_->threads = threads;
  impl_->arena = threads > 0 ? std::make_unique<tbb::task_arena>(threads) : nullptr;
}

const SubtreeSplit& CholeskyFactor::subtreeSplit() const {
  std::call_once(symbolic_->splitMade, [&] {
    symbolic_->split = std::make_unique<SubtreeSplit>(splitSupernodes(*symbolic_->L));
  });
  return *symbolic_->split;
}

void CholeskyFactor::solveSinglePrecision(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                          Workspace& work) const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor::solve before a factorisation");
  if (b.size() != rows()) throw std::invalid_argument("CholeskyFactor::solve: wrong size of b");
  prepareSinglePrecision();
  Workspace::Impl& w = *work.impl_;
  const float* Lx = numeric_->single->x.get();
  if (w.threads > 0)
    splitSupernodalSolve(*numeric_->L, Lx, subtreeSplit(), *w.arena, b, x, w.yf, w.tf, w.splitF);
  else
    supernodalSolve(*numeric_->L, Lx, b, x, w.yf, w.tf);
}

void CholeskyFactor::prepareSinglePrecision() const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor: no factorisation to round");
  const cholmod_factor& L = *numeric_->L;
  SingleCopy& single = *numeric_->single;
  std::call_once(single.made, [&] {
    const double* Lx = static_cast<const double*>(L.x);
    if (L.xsize == symbolic_->L->xsize) {
      single.x = symbolic_->takeSingle();
      single.from = symbolic_;
    } else {
      single.x = std::make_unique_for_overwrite<float[]>(L.xsize);
    }
    std::copy(Lx, Lx + L.xsize, single.x.get());
  });
}

void CholeskyFactor::solveSupernodalDouble(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                           Workspace& work) const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor::solve before a factorisation");
  if (b.size() != rows()) throw std::invalid_argument("CholeskyFactor::solve: wrong size of b");
  Workspace::Impl& w = *work.impl_;
  const auto* Lx = static_cast<const double*>(numeric_->L->x);
  if (w.threads > 0)
    splitSupernodalSolve(*numeric_->L, Lx, subtreeSplit(), *w.arena, b, x, w.yd, w.td, w.splitD);
  else
    supernodalSolve(*numeric_->L, Lx, b, x, w.yd, w.td);
}

void CholeskyFactor::forwardSolve(const Eigen::MatrixXd& B, std::vector<int>& rows,
                                  Eigen::MatrixXd& W) const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor::solve before a factorisation");
  if (B.rows() != this->rows())
    throw std::invalid_argument("CholeskyFactor::forwardSolve: wrong size of B");
  const cholmod_factor& L = *numeric_->L;
  const Supernodes<double> sn(L, static_cast<const double*>(L.x));
  const auto n = static_cast<Eigen::Index>(L.n);
  const auto nsuper = static_cast<int>(L.nsuper);
  const int* perm = static_cast<const int*>(L.Perm);
  // The supernodes that hold a non-zero row of P B, then their ancestors (a supernode's parent
  // holds the first row below its diagonal block; ancestors come later in the order).
  std::vector<int> superOf(L.n);
  for (int k = 0; k < nsuper; ++k)
    for (int c = sn.super[k]; c < sn.super[k + 1]; ++c) superOf[static_cast<size_t>(c)] = k;
  std::vector<char> onPath(static_cast<size_t>(nsuper), 0);
  // Row-major: the updates below a supernode subtract whole rows.
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor Y = RowMajor::Zero(n, B.cols());
  for (Eigen::Index i = 0; i < n; ++i)
    if (B.row(perm[i]).any()) {
      Y.row(i) = B.row(perm[i]);
      onPath[static_cast<size_t>(superOf[static_cast<size_t>(i)])] = 1;
    }
  RowMajor T;
  for (int k = 0; k < nsuper; ++k) {
    if (!onPath[static_cast<size_t>(k)]) continue;
    const auto p = sn.panel(k);
    auto Yk = Y.middleRows(p.first, p.nscol);
    p.block.topRows(p.nscol).triangularView<Eigen::Lower>().solveInPlace(Yk);
    if (p.below == 0) continue;
    T.noalias() = p.lower() * Yk;
    for (int i = 0; i < p.below; ++i) Y.row(p.rows[i]) -= T.row(i);
    const int parentRow = *std::min_element(p.rows, p.rows + p.below);
    onPath[static_cast<size_t>(superOf[static_cast<size_t>(parentRow)])] = 1;
  }
  rows.clear();
  for (int k = 0; k < nsuper; ++k)
    if (onPath[static_cast<size_t>(k)])
      for (int c = sn.super[k]; c < sn.super[k + 1]; ++c) rows.push_back(c);
  W.resize(static_cast<Eigen::Index>(rows.size()), B.cols());
  for (size_t r = 0; r < rows.size(); ++r) W.row(static_cast<Eigen::Index>(r)) = Y.row(rows[r]);
}

void CholeskyFactor::solveWithMidCorrection(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                            Workspace& work, bool singlePrecision,
                                            const MidCorrection& mid) const {
  if (!isFactorized()) throw std::logic_error("CholeskyFactor::solve before a factorisation");
  if (b.size() != rows()) throw std::invalid_argument("CholeskyFactor::solve: wrong size of b");
  Workspace::Impl& w = *work.impl_;
  const cholmod_factor& L = *numeric_->L;
  if (singlePrecision) {
    prepareSinglePrecision();
    const float* Lx = numeric_->single->x.get();
    // The correction works in double: c is widened, corrected and rounded back.
    const auto midFloat = [&](Eigen::VectorXf& y) {
      w.cd = y.cast<double>();
      mid(w.cd);
      y = w.cd.cast<float>();
    };
    if (w.threads > 0)
      splitSupernodalSolve(L, Lx, subtreeSplit(), *w.arena, b, x, w.yf, w.tf, w.splitF, midFloat);
    else
      supernodalSolve(L, Lx, b, x, w.yf, w.tf, midFloat);
  } else {
    const auto* Lx = static_cast<const double*>(L.x);
    const auto midDouble = [&](Eigen::VectorXd& y) { mid(y); };
    if (w.threads > 0)
      splitSupernodalSolve(L, Lx, subtreeSplit(), *w.arena, b, x, w.yd, w.td, w.splitD, midDouble);
    else
      supernodalSolve(L, Lx, b, x, w.yd, w.td, midDouble);
  }
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

void factorizeUnshared(std::shared_ptr<CholeskyFactor>& factor, const SparseMatrix& A,
                       int threads) {
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
  factor->factorize(A, threads);
}

}  // namespace bcassim
