#include "bcassim/mechanics/solvers/JacobiPcgSolver.h"

#include <stdexcept>

#include "bcassim/mechanics/solvers/LinearSolveError.h"

namespace bcassim {

void JacobiPcgSolver::setMatrix(const SparseMatrix& A) {
  jacobi_.compute(A);
  A_ = &A;
}

SolveStatus JacobiPcgSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (A_ == nullptr) throw std::logic_error("JacobiPcgSolver::solve before setMatrix");
  const int maxIter = maxIterations_ > 0 ? maxIterations_ : static_cast<int>(A_->rows());
  return requireConverged(preconditionedCg(*A_, b, x, jacobi_, relTol_, maxIter, work_), name(),
                          relTol_);
}

}  // namespace bcassim
