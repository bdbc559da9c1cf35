// PCG preconditioned by a stored Cholesky factorisation of an earlier matrix (thesis §4.5,
// Alg. 4/5): the factorisation is computed rarely and reused across solves, time steps and,
// shared read-only, across the sigma points solved in parallel threads.
#pragma once
#include <future>
#include <memory>

#include "bcassim/BackgroundThread.h"
#include "bcassim/mechanics/solvers/CholeskyFactor.h"
#include "bcassim/mechanics/solvers/ConjugateGradient.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

// When the stored factorisation is recomputed from the current matrix.
struct RefreshPolicy {
  int everyNMatrices =
      0;  // after this many setMatrix calls since the last factorisation; 0 = never
  int maxIterations = 20;  // when PCG does not converge within this many iterations
  double relTol = 1e-10;   // PCG stopping tolerance on |b - A x| / |b|
  // Refreshes due by count run on another thread while the old factor keeps preconditioning; the
  // new one is used from the first solve after it is ready (a core of its own hides its cost).
  bool background = false;
  // Precondition with the factor rounded to single precision: about half the time per PCG
  // iteration (the triangular solves are memory-bound), sometimes an iteration more. The
  // solution is still converged to relTol in double precision.
  bool singlePrecision = true;
};

class FactorizedPcgSolver final : public LinearSolver {
 public:
  // Owns its factorisation, computed at the first setMatrix.
  explicit FactorizedPcgSolver(RefreshPolicy policy = {});
  // Preconditions with factor, typically another solver's factor(), until the policy asks for a
  // refresh; then this solver factorises into a factor of its own and never modifies the shared
  // one. A factor that is already factorised makes the first setMatrix factorisation-free.
  explicit FactorizedPcgSolver(std::shared_ptr<CholeskyFactor> factor, RefreshPolicy policy = {});

  // Keeps the current factor if it was analysed for a pattern of A's size and entry count.
  void analyzePattern(const SparseMatrix& A) override;
  // Factorises A if there is no factorisation yet or everyNMatrices calls have passed since the
  // last one (matrices 1, N+1, 2N+1, ... of an owning solver).
  void setMatrix(const SparseMatrix& A) override;
  // PCG from x; if it has not converged after policy().maxIterations, factorises the current
  // matrix, solves directly and confirms by PCG (status.refactorized = true). Iterations of both
  // runs are counted. Throws LinearSolveError if the confirmation does not converge either.
  SolveStatus solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  std::string name() const override { return "factorized-pcg"; }

  const std::shared_ptr<CholeskyFactor>& factor() const { return factor_; }
  // Adopts another factor (e.g. the one refreshed by the first sigma point); the count towards
  // everyNMatrices restarts as for the sharing constructor.
  void shareFactor(std::shared_ptr<CholeskyFactor> factor);
  const RefreshPolicy& policy() const { return policy_; }
  // Factorisations computed by this solver so far.
  int factorizations() const { return factorizations_; }

 private:
  void refactorize();

  RefreshPolicy policy_;
  std::shared_ptr<CholeskyFactor> factor_;
  const SparseMatrix* A_ = nullptr;
  int matricesSinceFactorization_ = 0;
  int factorizations_ = 0;
  CholeskyFactor::Workspace factorWork_;
  CgWorkspace cgWork_;
  // Adopts a background factorisation once it is ready.
  void adoptFinishedRefresh();
  std::future<std::shared_ptr<CholeskyFactor>> pending_;
  // policy.background: every refresh on one thread, started at the first (BackgroundThread.h).
  std::unique_ptr<BackgroundThread> refresher_;
};

}  // namespace bcassim
