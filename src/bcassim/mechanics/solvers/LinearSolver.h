// The interface every sparse linear solver of bcassim implements: set a matrix (A is symmetric
// positive definite, both triangles stored), then solve A x = b for one or many right-hand sides.
#pragma once
#include <memory>
#include <string>

#include "bcassim/Types.h"

namespace bcassim {

struct SolveStatus {
  // Always true from a LinearSolver (an iterative one throws LinearSolveError instead); false
  // from the free function preconditionedCg when it stopped at its iteration limit.
  bool converged = true;
  int iterations = 0;             // 0 for direct solves
  double relativeResidual = 0.0;  // |b - A x| / |b| as measured by the solver (0 if not measured)
  bool refactorized = false;      // a factorisation was (re)computed during this call
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  // Symbolic analysis of the fixed sparsity pattern; call once (or again if the pattern changes).
  virtual void analyzePattern(const SparseMatrix& A) = 0;
  // New numerical values for the matrix analysed before. The solver keeps a reference to A, which
  // must outlive the following solve() calls. Direct solvers factorise here; iterative ones
  // may not.
  virtual void setMatrix(const SparseMatrix& A) = 0;
  // Solves A x = b. x holds the initial guess on entry (used by iterative solvers; a vector of the
  // wrong size counts as zero). An instance is used by one thread at a time. An iterative solver
  // that stops short of its tolerance throws LinearSolveError (it never returns a non-solution).
  virtual SolveStatus solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) = 0;
  virtual std::string name() const = 0;
  // Threads the next factorisations may use (a direct solver's; others ignore it), for a solve
  // that has the cores to itself. The result does not depend on it.
  virtual void setFactorThreads(int /*threads*/) {}
};

}  // namespace bcassim
