// A sparse Cholesky factorisation A = L L^T (CHOLMOD, supernodal) that can be computed once and
// then used read-only by many threads, e.g. as the preconditioner shared by all sigma points.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "bcassim/Types.h"

namespace bcassim {

struct SubtreeSplit;

class CholeskyFactor {
 public:
  // Scratch memory of solve(): CHOLMOD's cholmod_common and dense buffers. Give each thread its
  // own (a solver keeps one) so that repeated solves allocate nothing.
  class Workspace {
   public:
    Workspace();
    ~Workspace();
    Workspace(Workspace&&) noexcept;
    Workspace& operator=(Workspace&&) noexcept;
    // 0 (the default): the supernodal sweeps of solveSinglePrecision and solveSupernodalDouble run
    // on the calling thread. N >= 1: their elimination tree is cut into 4 fixed groups of subtrees
    // run on up to N threads (the same bits for every N >= 1, differing from 0's by round-off),
    // for a solve that has the cores to itself (a model's mean, not sigma points in parallel).
    void setThreads(int threads);

   private:
    friend class CholeskyFactor;
    struct Impl;
    std::unique_ptr<Impl> impl_;
  };

  CholeskyFactor();
  ~CholeskyFactor();
  CholeskyFactor(const CholeskyFactor&) = delete;
  CholeskyFactor& operator=(const CholeskyFactor&) = delete;

  // Fill-reducing ordering (AMD or METIS, as CHOLMOD chooses) and supernodal symbolic analysis of
  // the pattern of A. A is symmetric with both triangles stored; only the lower one is read.
  void analyzePattern(const SparseMatrix& A);
  // Numerical factorisation of A, whose pattern was analysed (analyses it first if not), on up
  // to `threads` threads: bcassim's left-looking supernodal factorisation (SupernodalCholesky)
  // into CHOLMOD's layout, 1.6x faster than CHOLMOD's own on one thread (docs/benchmarks.md §6),
  // the elimination tree's 4 fixed groups of subtrees concurrently, then the supernodes above
  // them. The same bits for any number of threads. Throws NumericalError if A is not positive
  // definite; the factor is then unusable. A pattern other than the first one factorised (same
  // size and entry count, other rows) goes to CHOLMOD's factorisation.
  void factorize(const SparseMatrix& A, int threads = 1);
  // CHOLMOD's numerical factorisation (the reference of the tests and benchmarks; the same
  // errors). The BLAS work runs on the calling thread; CHOLMOD 3 itself runs a few O(n) copy
  // loops under OpenMP here (solves never do).
  void factorizeWithCholmod(const SparseMatrix& A);
  // A new, unfactorised CholeskyFactor that shares this one's symbolic analysis (read-only), so
  // factorising it costs only the numerical phase. This factor is left untouched.
  std::shared_ptr<CholeskyFactor> cloneAnalysis() const;

  // x = A^{-1} b with the last factorised A. Const and thread-safe: any number of threads may
  // call solve() concurrently, each with its own workspace (or none), while nobody calls
  // analyzePattern() or factorize() on this object.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, Workspace& work) const;
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  // Block of right-hand sides, one per column of B: X = A^{-1} B in one sweep over L.
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X, Workspace& work) const;
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const;
  // x ~ A^{-1} b with L rounded to single precision (a copy made at the first call after each
  // factorisation): relative error ~1e-6 times A's condition, so only for preconditioning. The
  // supernodal solves are memory-bound; a float L halves their traffic, and a factor that fits
  // in a core's cache only as floats stops the sigma-point threads competing for memory.
  // Thread-safe like solve().
  void solveSinglePrecision(const Eigen::VectorXd& b, Eigen::VectorXd& x, Workspace& work) const;
  // Makes that float copy now (e.g. on the thread that factorised) instead of at the first
  // single-precision solve.
  void prepareSinglePrecision() const;
  // The same supernodal sweep in double precision on L itself (a check of the float path; CHOLMOD's
  // solve() is the production double path).
  void solveSupernodalDouble(const Eigen::VectorXd& b, Eigen::VectorXd& x, Workspace& work) const;

  // The forward half of a block solve, for right-hand sides with few non-zero rows (the
  // attachments of a few springs): W = L^{-1} P B, of which only the rows on the elimination-tree
  // paths from B's non-zero rows to the root can be non-zero. Sets `rows` to those rows (in L's
  // ordering, ascending) and W to them alone (rows.size() x B.cols()). Costs a fraction of
  // solve(B, X): no supernode off those paths, no backward sweep. Double precision, on L itself.
  void forwardSolve(const Eigen::MatrixXd& B, std::vector<int>& rows, Eigen::MatrixXd& W) const;
  // A correction between the two sweeps of a solve: gets c = L^{-1} P b (double, in L's
  // ordering) and changes it in place; the solve returns P^T L^{-T} c. With the W of
  // forwardSolve this applies a low-rank update's Woodbury correction without A^{-1} U.
  using MidCorrection = std::function<void(Eigen::VectorXd& c)>;
  // x = P^T L^{-T} mid(L^{-1} P b) by this class' supernodal sweeps: in double on L (like
  // solveSupernodalDouble) or with L rounded to float (like solveSinglePrecision), split over
  // the workspace's threads as those are. Thread-safe like solve().
  void solveWithMidCorrection(const Eigen::VectorXd& b, Eigen::VectorXd& x, Workspace& work,
                              bool singlePrecision, const MidCorrection& mid) const;

  bool isAnalyzed() const;
  bool isFactorized() const;
  Eigen::Index rows() const;
  // Whether A has the size and number of stored entries of the analysed pattern (a cheap check
  // that the analysis applies to A).
  bool matchesPattern(const SparseMatrix& A) const;
  // Entries of L (from the symbolic analysis), for reports of memory and cost.
  std::int64_t factorNonZeros() const;

 private:
  const SubtreeSplit& subtreeSplit() const;
  struct Symbolic;
  std::shared_ptr<const Symbolic> symbolic_;
  struct SingleCopy;
  struct Numeric;
  std::unique_ptr<Numeric> numeric_;
};

// Factorises A into factor without disturbing anyone else who holds it: a factor shared with
// other owners (threads may be solving with it) is replaced by a fresh one that reuses its
// analysis; a factor held only here is refactorised in place. On up to `threads` threads.
void factorizeUnshared(std::shared_ptr<CholeskyFactor>& factor, const SparseMatrix& A,
                       int threads = 1);

}  // namespace bcassim
