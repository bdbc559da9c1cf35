// Unpreconditioned conjugate gradients behind the LinearSolver interface: the baseline that
// needs no setup, only matrix-vector products.
#pragma once
#include "bcassim/mechanics/solvers/ConjugateGradient.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

class CgSolver final : public LinearSolver {
 public:
  // Stops at |b - A x| / |b| <= relTol; throws LinearSolveError if maxIterations (0: the size
  // of the matrix) did not get there.
  explicit CgSolver(double relTol = 1e-10, int maxIterations = 0)
      : relTol_(relTol), maxIterations_(maxIterations) {}
  void analyzePattern(const SparseMatrix&) override {}
  void setMatrix(const SparseMatrix& A) override { A_ = &A; }
  SolveStatus solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  std::string name() const override { return "cg"; }

 private:
  const SparseMatrix* A_ = nullptr;
  double relTol_;
  int maxIterations_;
  IdentityPreconditioner identity_;
  CgWorkspace work_;
};

}  // namespace bcassim
