#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"

#include <chrono>
#include <stdexcept>

#include "bcassim/mechanics/solvers/CholeskyPreconditioner.h"
#include "bcassim/mechanics/solvers/LinearSolveError.h"

namespace bcassim {

FactorizedPcgSolver::FactorizedPcgSolver(RefreshPolicy policy)
    : FactorizedPcgSolver(std::make_shared<CholeskyFactor>(), policy) {}

FactorizedPcgSolver::FactorizedPcgSolver(std::shared_ptr<CholeskyFactor> factor,
                                         RefreshPolicy policy)
    : policy_(policy), factor_(factor ? std::move(factor) : std::make_shared<CholeskyFactor>()) {}

void FactorizedPcgSolver::analyzePattern(const SparseMatrix& A) {
  if (factor_->isAnalyzed() && factor_->matchesPattern(A)) return;
  auto factor = std::make_shared<CholeskyFactor>();
  factor->analyzePattern(A);
  factor_ = std::move(factor);
  matricesSinceFactorization_ = 0;
}

void FactorizedPcgSolver::setMatrix(const SparseMatrix& A) {
  A_ = &A;
  ++matricesSinceFactorization_;
  const bool due =
      policy_.everyNMatrices > 0 && matricesSinceFactorization_ > policy_.everyNMatrices;
  adoptFinishedRefresh();
  const bool stale = !factor_->isFactorized() || !factor_->matchesPattern(A);
  if (!stale && due && policy_.background) {
    if (!pending_.valid()) {
      std::shared_ptr<CholeskyFactor> next = factor_->cloneAnalysis();
      if (!refresher_) refresher_ = std::make_unique<BackgroundThread>();
      pending_ =
          refresher_->submit([next, copy = SparseMatrix(A), single = policy_.singlePrecision] {
            next->factorize(copy);
            if (single) next->prepareSinglePrecision();
            return next;
          });
    }
    matricesSinceFactorization_ = 1;
  } else if (stale || due) {
    refactorize();
  }
}

void FactorizedPcgSolver::adoptFinishedRefresh() {
  if (!pending_.valid() || pending_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
    return;
  factor_ = pending_.get();
  ++factorizations_;
}

void FactorizedPcgSolver::refactorize() {
  factorizeUnshared(factor_, *A_);
  if (policy_.singlePrecision) factor_->prepareSinglePrecision();
  matricesSinceFactorization_ = 1;
  ++factorizations_;
}

void FactorizedPcgSolver::shareFactor(std::shared_ptr<CholeskyFactor> factor) {
  if (!factor) throw std::invalid_argument("FactorizedPcgSolver::shareFactor: null factor");
  factor_ = std::move(factor);
  matricesSinceFactorization_ = 0;
}

SolveStatus FactorizedPcgSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (A_ == nullptr) throw std::logic_error("FactorizedPcgSolver::solve before setMatrix");
  adoptFinishedRefresh();
  SolveStatus first = preconditionedCg(
      *A_, b, x, CholeskyPreconditioner(*factor_, factorWork_, policy_.singlePrecision),
      policy_.relTol, policy_.maxIterations, cgWork_);
  if (first.converged) return first;

  // The stored factorisation no longer preconditions A well: factorise A itself. Its direct
  // solution is exact up to rounding, so PCG from there only confirms (or refines) it.
  refactorize();
  factor_->solve(b, x, factorWork_);
  SolveStatus second = preconditionedCg(
      *A_, b, x, CholeskyPreconditioner(*factor_, factorWork_, policy_.singlePrecision),
      policy_.relTol, policy_.maxIterations, cgWork_);
  second.iterations += first.iterations;
  second.refactorized = true;
  // Even A's own factor did not get there: A is too ill-conditioned for the tolerance.
  if (!second.converged)
    throw LinearSolveError(name(), second, policy_.relTol, ", even with A itself factorised");
  return second;
}

}  // namespace bcassim
