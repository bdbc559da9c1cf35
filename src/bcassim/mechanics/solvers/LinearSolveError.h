// The error an iterative linear solver throws when it stops short of its tolerance: a solution
// that is not one is never returned. Names the solver, its iterations and the residual reached.
#pragma once
#include <fmt/format.h>

#include <string>

#include "bcassim/Error.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

class LinearSolveError : public NumericalError {
 public:
  LinearSolveError(const std::string& solver, const SolveStatus& status, double relTol,
                   const std::string& note = "")
      : NumericalError(fmt::format("{} did not converge: relative residual {:.3g} after {} "
                                   "iterations (tolerance {:.3g}){}",
                                   solver, status.relativeResidual, status.iterations, relTol,
                                   note)),
        status_(status) {}

  const SolveStatus& status() const { return status_; }

 private:
  SolveStatus status_;
};

// Throws LinearSolveError unless status converged; returns it otherwise.
inline SolveStatus requireConverged(const SolveStatus& status, const std::string& solver,
                                    double relTol) {
  if (!status.converged) throw LinearSolveError(solver, status, relTol);
  return status;
}

}  // namespace bcassim
