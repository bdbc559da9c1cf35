// Direct solver: CHOLMOD supernodal Cholesky, analysed once per pattern and factorised for
// every matrix; solves are exact up to rounding.
#pragma once
#include <memory>

#include "bcassim/mechanics/solvers/CholeskyFactor.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

class CholmodSolver final : public LinearSolver {
 public:
  CholmodSolver();
  // Starts from `analysed`'s symbolic analysis (CholeskyFactor::cloneAnalysis; null: none), e.g.
  // another solver's of the same pattern: one fill-reducing ordering instead of two, and the
  // supernodal plan and spare values of that analysis shared.
  explicit CholmodSolver(std::shared_ptr<CholeskyFactor> analysed);
  // Analyses A's pattern, unless the analysis held already matches it.
  void analyzePattern(const SparseMatrix& A) override;
  // Factorises A; throws NumericalError if A is not positive definite.
  void setMatrix(const SparseMatrix& A) override;
  SolveStatus solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  std::string name() const override { return "cholmod"; }
  void setFactorThreads(int threads) override { threads_ = threads; }
  // The factor of the last matrix, e.g. to precondition other solvers (see FactorizedPcgSolver).
  // Later setMatrix calls factorise into a new object while it is held elsewhere.
  const std::shared_ptr<CholeskyFactor>& factor() const { return factor_; }

 private:
  std::shared_ptr<CholeskyFactor> factor_;
  CholeskyFactor::Workspace work_;
  int threads_ = 1;
};

}  // namespace bcassim
