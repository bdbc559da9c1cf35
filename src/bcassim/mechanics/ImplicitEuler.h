// Implicit Euler time stepping exactly as thesis eq. 2.16: one linearisation per step,
// (M + dt D + dt^2 K) a = f_ext - f_int - D v - dt K v, D = zeta_M M + zeta_K K (eq. 2.15);
// optional further Newton iterations on the nonlinear backward-Euler residual. A step that fails
// is redone as two of half the size, as FEBio's automatic time stepping does.
#pragma once
#include <memory>

#include "bcassim/Error.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/StepFailure.h"
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
  // s: a step that fails (an element inverted, a linear solve or Newton not converged, a
  // non-finite state) is redone from its start as two steps of half the size, recursively, as
  // long as they stay at least this long; 0 means dt / 64 (six halvings); dt means no retry.
  double minDt = 0.0;
};

// Wall-clock seconds spent in the parts of the last step.
struct StepTimings {
  double assembly = 0, solve = 0, total = 0;
  SolveStatus lastSolve;
  int linearSolves = 0;
  int retries = 0;  // failed attempts redone as two half steps (0 for a step that went through)
};

class ImplicitEuler {
 public:
  ImplicitEuler(const MechanicalModel& model, std::unique_ptr<LinearSolver> solver,
                ImplicitEulerOptions options);

  // Advances state by one time step dt, halving it where it fails (ImplicitEulerOptions::minDt;
  // lastTimings().retries counts the halvings). Throws StepFailure when a step of the smallest
  // size fails too, or when an element is inverted in the state the step starts from; the state
  // is then undefined.
  void step(const MechanicalModel& model, MechanicalState& state);

  // Eq. 2.16 with the stiffness of `tangent` (assembled at another state, or with other
  // parameters) in place of K(x): a one-stage Rosenbrock-W step. Forces are this state's own; no
  // tangent is assembled and nothing is factorised, so the step costs a force assembly and one
  // solve with the shared factor. Consistent (first order) for any tangent; the same as step()
  // when the tangent is that of this state. If the tangent corrects springs
  // (FrozenTangent::correctsSprings), the springs' stiffness is this state's own (with this
  // model's coefficients), exactly, by a low-rank correction: only the elastic part is frozen.
  // Extra Newton iterations are not run. A step that fails is redone as step() does it, with the
  // state's own tangents (the shared one is for dt only). Throws InputError if the tangent was
  // built for another dt, StepFailure as step(). singlePrecision: the solve through the factor
  // rounded to float (FrozenTangent::solve): half its memory traffic, and a velocity change off by
  // ~1e-6 times the system's condition (relative); for steps whose start is reset often (the live
  // real-time model, which adopts each analysis; a filter's sigma points, from each analysed mean).
  void stepWithTangent(const MechanicalModel& model, MechanicalState& state,
                       const FrozenTangent& tangent, bool singlePrecision = false);

  const StepTimings& lastTimings() const { return timings_; }
  const ImplicitEulerOptions& options() const { return options_; }
  LinearSolver& linearSolver() { return *solver_; }

 private:
  // A = (1 + h zM) M + (h zK + h^2) K where K is the stiffness already in A_.
  void formSystemMatrix(const MechanicalModel& model, double h);
  // A step of h from s; when it fails, two of h / 2 from the same start (halve), recursively.
  void advance(const MechanicalModel& model, MechanicalState& s, double h);
  void halve(const MechanicalModel& model, MechanicalState& s, double h,
             const NumericalError& failure);
  // One try at a step of h from `from` into s (equal to `from` on entry). Throws NumericalError
  // when it fails (StepFailure when no smaller step can help).
  void attempt(const MechanicalModel& model, const MechanicalState& from, double h,
               MechanicalState& s);
  void attemptWithTangent(const MechanicalModel& model, MechanicalState& s,
                          const FrozenTangent& tangent, bool singlePrecision);
  // Throws unless the end state of a step is finite and has no inverted element.
  void checkEndState(const MechanicalModel& model, const MechanicalState& s,
                     bool forcesSeenThere) const;

  std::unique_ptr<LinearSolver> solver_;
  ImplicitEulerOptions options_;
  SparseMatrix A_;
  Eigen::VectorXd fint_, fext_, Mv_, Kv_, rhs_, dv_, rest_, knownDv_;
  Eigen::VectorXd stepDv_, previousStepDv_;  // velocity changes of the last two steps
  CholeskyFactor::Workspace factorWork_;
  StepTimings timings_;
};

}  // namespace bcassim
