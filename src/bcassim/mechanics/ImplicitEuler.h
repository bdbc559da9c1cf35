// Implicit Euler time stepping exactly as thesis eq. 2.16: one linearisation per step,
// (M + dt D + dt^2 K) a = f_ext - f_int - D v - dt K v, D = zeta_M M + zeta_K K (eq. 2.15);
// optional further Newton iterations on the nonlinear backward-Euler residual.
#pragma once
#include <memory>

#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

struct ImplicitEulerOptions {
  double dt = 0.01;                // s
  int newtonIterations = 0;        // extra Newton iterations after the eq. 2.16 step (0 = thesis)
  double newtonTolerance = 1e-10;  // relative residual norm that stops the extra iterations
  // Initial guess of an iterative solver: the linear extrapolation 2 dv_n - dv_(n-1) of the last
  // two steps' velocity changes (else the last one). For one trajectory; an integrator that
  // steps many different states in turn (sigma points) should use only the last one.
  bool extrapolateGuess = true;
};

// Wall-clock seconds spent in the parts of the last step.
struct StepTimings {
  double assembly = 0, solve = 0, total = 0;
  SolveStatus lastSolve;
  int linearSolves = 0;
};

class ImplicitEuler {
 public:
  ImplicitEuler(const MechanicalModel& model, std::unique_ptr<LinearSolver> solver,
                ImplicitEulerOptions options);

  // Advances state by one time step dt. Throws NumericalError if the result is not finite.
  void step(const MechanicalModel& model, MechanicalState& state);

  // Eq. 2.16 with the stiffness of `tangent` (assembled at another state, or with other
  // parameters) in place of K(x): a one-stage Rosenbrock-W step. Forces are this state's own; no
  // tangent is assembled and nothing is factorised, so the step costs a force assembly and one
  // solve with the shared factor. Consistent (first order) for any tangent; the same as step()
  // when the tangent is that of this state. If the tangent corrects springs
  // (FrozenTangent::correctsSprings), the springs' stiffness is this state's own (with this
  // model's coefficients), exactly, by a low-rank correction: only the elastic part is frozen.
  // Extra Newton iterations are not run. Throws InputError if the tangent was built for another
  // dt, NumericalError as step().
  void stepWithTangent(const MechanicalModel& model, MechanicalState& state,
                       const FrozenTangent& tangent);

  const StepTimings& lastTimings() const { return timings_; }
  const ImplicitEulerOptions& options() const { return options_; }
  LinearSolver& linearSolver() { return *solver_; }

 private:
  // A = (1 + dt zM) M + (dt zK + dt^2) K where K is the stiffness already in A_.
  void formSystemMatrix(const MechanicalModel& model);
  void checkFinite(const MechanicalModel& model, const MechanicalState& s) const;

  std::unique_ptr<LinearSolver> solver_;
  ImplicitEulerOptions options_;
  SparseMatrix A_;
  Eigen::VectorXd fint_, fext_, Mv_, Kv_, rhs_, dv_, rest_, knownDv_;
  Eigen::VectorXd stepDv_, previousStepDv_;  // velocity changes of the last two steps
  CholeskyFactor::Workspace factorWork_;
  StepTimings timings_;
};

}  // namespace bcassim
