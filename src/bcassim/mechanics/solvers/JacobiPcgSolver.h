// Conjugate gradients preconditioned by the diagonal of A: cheap to set up for every matrix,
// the reference that the stored-factorisation preconditioner is measured against.
#pragma once
#include "bcassim/mechanics/solvers/ConjugateGradient.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

class JacobiPcgSolver final : public LinearSolver {
 public:
  // Stops at |b - A x| / |b| <= relTol; throws LinearSolveError if maxIterations (0: the size
  // of the matrix) did not get there.
  explicit JacobiPcgSolver(double relTol = 1e-10, int maxIterations = 0)
      : relTol_(relTol), maxIterations_(maxIterations) {}
  void analyzePattern(const SparseMatrix&) override {}
  // Throws NumericalError if a diagonal entry is not positive.
  void setMatrix(const SparseMatrix& A) override;
  SolveStatus solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  std::string name() const override { return "jacobi-pcg"; }

 private:
  const SparseMatrix* A_ = nullptr;
  double relTol_;
  int maxIterations_;
  JacobiPreconditioner jacobi_;
  CgWorkspace work_;
};

}  // namespace bcassim
