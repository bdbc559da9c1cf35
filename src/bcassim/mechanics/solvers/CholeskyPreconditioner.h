// Preconditioning by a stored Cholesky factorisation of an earlier matrix (thesis §4.5): z = L^-T
// L^-1 r, exact for the matrix that was factorised and close for its small perturbations.
#pragma once
#include "bcassim/mechanics/solvers/CholeskyFactor.h"
#include "bcassim/mechanics/solvers/ConjugateGradient.h"

namespace bcassim {

// Borrows a factorised factor and a workspace; both must outlive it. Thread-safe to the extent
// that each thread uses its own workspace (the factor is only read).
class CholeskyPreconditioner final : public Preconditioner {
 public:
  // singlePrecision: apply L rounded to float (CholeskyFactor::solveSinglePrecision).
  CholeskyPreconditioner(const CholeskyFactor& factor, CholeskyFactor::Workspace& work,
                         bool singlePrecision = false)
      : factor_(factor), work_(work), singlePrecision_(singlePrecision) {}
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override {
    if (singlePrecision_)
      factor_.solveSinglePrecision(r, z, work_);
    else
      factor_.solve(r, z, work_);
  }

 private:
  const CholeskyFactor& factor_;
  CholeskyFactor::Workspace& work_;
  bool singlePrecision_;
};

}  // namespace bcassim
