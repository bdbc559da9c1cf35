#include "bcassim/mechanics/solvers/CgSolver.h"

#include <stdexcept>

#include "bcassim/mechanics/solvers/LinearSolveError.h"

namespace bcassim {

SolveStatus CgSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (A_ == nullptr) throw std::logic_error("CgSolver::solve before setMatrix");
  const int maxIter = maxIterations_ > 0 ? maxIterations_ : static_cast<int>(A_->rows());
  return requireConverged(preconditionedCg(*A_, b, x, identity_, relTol_, maxIter, work_), name(),
                          relTol_);
}

}  // namespace bcassim
