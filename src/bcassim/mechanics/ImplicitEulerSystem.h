// The two pieces of eq. 2.16 every implicit-Euler variant forms the same way: the system matrix
// from the stiffness, and the velocity changes that bring Dirichlet dofs to their targets.
#pragma once
#include "bcassim/mechanics/MechanicalModel.h"

namespace bcassim {

// Multiplier of K in the system matrix: dt zeta_K + dt^2.
inline double implicitEulerStiffnessScale(const MechanicalModel& model, double dt) {
  return dt * model.rayleighStiffness + dt * dt;
}

// Turns K (the pattern's structure) into A = (1 + dt zeta_M) M + (dt zeta_K + dt^2) K, in place.
inline void stiffnessToImplicitEulerMatrix(const MechanicalModel& model, double dt,
                                           SparseMatrix& K) {
  K.coeffs() *= implicitEulerStiffnessScale(model, dt);
  model.mass.addTo(*model.pattern, 1.0 + dt * model.rayleighMass, K);
}

// dv of the constrained dofs (constrainedDofs() order) so that x + dt (v + dv) reaches their
// prescribed positions at time tNext.
inline void knownVelocityChange(const MechanicalModel& model, const Eigen::VectorXd& rest,
                                const MechanicalState& s, double dt, double tNext,
                                Eigen::VectorXd& dv) {
  const DirichletConditions& bc = model.dirichlet;
  const Eigen::VectorXd target = bc.targetPositions(rest, tNext);
  dv.resize(target.size());
  for (Eigen::Index k = 0; k < target.size(); ++k) {
    const int d = bc.constrainedDofs()[k];
    dv(k) = (target(k) - s.x(d)) / dt - s.v(d);
  }
}

}  // namespace bcassim
