// The implicit-Euler matrix of one linearisation point, factorised once and shared read-only by
// many integrations: the W of a linearly implicit (Rosenbrock-W) Euler step, e.g. the tangent at
// a Kalman filter's mean used by all of its sigma points.
#pragma once
#include <memory>

#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/solvers/CholeskyFactor.h"

namespace bcassim {

class FrozenTangent {
 public:
  // Assembles K at (state.x, state.t) with the model as it is now (its parameters included),
  // forms A = (1 + dt zeta_M) M + (dt zeta_K + dt^2) K (eq. 2.16) and factorises A with the
  // Dirichlet dofs eliminated. `analysis`, if given, is a factor whose symbolic analysis of the
  // model's pattern is reused (no new ordering). dt in s. Throws NumericalError if A is not
  // positive definite.
  static std::shared_ptr<const FrozenTangent> build(const MechanicalModel& model,
                                                    const MechanicalState& state, double dt,
                                                    const CholeskyFactor* analysis = nullptr);

  double dt() const { return dt_; }
  // K at the linearisation point (N/m), with the pattern's structure.
  const SparseMatrix& stiffness() const { return K_; }
  // A before Dirichlet elimination: its constrained columns move known values to a right-hand side.
  const SparseMatrix& systemMatrix() const { return A_; }
  // Factor of A with the Dirichlet rows and columns eliminated.
  const CholeskyFactor& factor() const { return *factor_; }
  // Seconds spent building (assembly + factorisation), for timings.
  double buildSeconds() const { return buildSeconds_; }

 private:
  double dt_ = 0, buildSeconds_ = 0;
  SparseMatrix K_, A_;
  std::shared_ptr<CholeskyFactor> factor_;
};

}  // namespace bcassim
