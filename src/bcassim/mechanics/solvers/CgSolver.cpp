#include "bcassim/mechanics/solvers/CgSolver.h"

#include <stdexcept>

namespace bcassim {

SolveStatus CgSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (A_ == nullptr) throw std::logic_error("CgSolver::solve before setMatrix");
  const int maxIter = maxIterations_ > 0 ? maxIterations_ : static_cast<int>(A_->rows());
  return preconditionedCg(*A_, b, x, identity_, relTol_, maxIter, work_);
}

}  // namespace bcassim
