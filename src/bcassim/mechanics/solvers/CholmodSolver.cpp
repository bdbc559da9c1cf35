#include "bcassim/mechanics/solvers/CholmodSolver.h"

#include <stdexcept>

namespace bcassim {

CholmodSolver::CholmodSolver() : factor_(std::make_shared<CholeskyFactor>()) {}

CholmodSolver::CholmodSolver(std::shared_ptr<CholeskyFactor> analysed)
    : factor_(analysed ? std::move(analysed) : std::make_shared<CholeskyFactor>()) {}

void CholmodSolver::analyzePattern(const SparseMatrix& A) {
  if (factor_->isAnalyzed() && factor_->matchesPattern(A)) return;
  auto factor = std::make_shared<CholeskyFactor>();
  factor->analyzePattern(A);
  factor_ = std::move(factor);
}

void CholmodSolver::setMatrix(const SparseMatrix& A) { factorizeUnshared(factor_, A, threads_); }

SolveStatus CholmodSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factor_->isFactorized()) throw std::logic_error("CholmodSolver::solve before setMatrix");
  factor_->solve(b, x, work_);
  return SolveStatus{};
}

}  // namespace bcassim
