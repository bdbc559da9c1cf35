#include "bcassim/mechanics/ImplicitEuler.h"

#include <fmt/format.h>

#include <Eigen/LU>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/mechanics/ImplicitEulerSystem.h"
#include "bcassim/mechanics/ResidualFloor.h"

namespace bcassim {
namespace {
constexpr const char* kIntegrator = "implicit Euler";

// An element inverted before the step: no smaller step can mend that.
StepFailure invertedAtStart(const InvertedElementError& e, double t) {
  return StepFailure(kIntegrator, t, std::string(e.what()) + " in the state the step starts from");
}
}  // namespace

ImplicitEuler::ImplicitEuler(const MechanicalModel& model, std::unique_ptr<LinearSolver> solver,
                             ImplicitEulerOptions options)
    : solver_(std::move(solver)), options_(options), A_(model.pattern->emptyMatrix()) {
  if (!(options_.dt > 0)) throw InputError("implicit Euler: dt must be positive (s)");
  if (options_.minDt == 0.0) options_.minDt = options_.dt / 64.0;
  if (!(options_.minDt > 0) || options_.minDt > options_.dt)
    throw InputError(
        fmt::format("implicit Euler: min_dt must be in (0, dt = {:.6g} s], got {:.6g} s",
                    options_.dt, options_.minDt));
  solver_->analyzePattern(A_);
  rest_ = model.restPositions();
}

void ImplicitEuler::formSystemMatrix(const MechanicalModel& model, double h) {
  stiffnessToImplicitEulerMatrix(model, h, A_);
}

void ImplicitEuler::step(const MechanicalModel& model, MechanicalState& s) {
  const auto start = Clock::now();
  timings_ = {};
  const Eigen::VectorXd v0 = s.v;
  advance(model, s, options_.dt);
  previousStepDv_.swap(stepDv_);
  stepDv_ = s.v - v0;
  timings_.total = secondsBetween(start, Clock::now());
}

void ImplicitEuler::advance(const MechanicalModel& model, MechanicalState& s, double h) {
  const MechanicalState from = s;
  try {
    attempt(model, from, h, s);
  } catch (const StepFailure&) {
    throw;
  } catch (const NumericalError& e) {
    s = from;
    halve(model, s, h, e);
  }
}

void ImplicitEuler::halve(const MechanicalModel& model, MechanicalState& s, double h,
                          const NumericalError& failure) {
  if (h / 2 < options_.minDt)
    throw StepFailure(
        kIntegrator, s.t,
        h < options_.dt
            ? fmt::format("{} with the time step halved to {:.6g} s (time.min_dt = {:.6g} s)",
                          failure.what(), h, options_.minDt)
            : fmt::format("{} at the time step {:.6g} s (time.min_dt = {:.6g} s allows no "
                          "halving)",
                          failure.what(), h, options_.minDt));
  ++timings_.retries;
  advance(model, s, h / 2);
  advance(model, s, h / 2);
}

void ImplicitEuler::attempt(const MechanicalModel& model, const MechanicalState& from, double h,
                            MechanicalState& s) {
  const double tNext = from.t + h;
  const DirichletConditions& bc = model.dirichlet;

  // Eq. 2.16, linearised at the current state.
  auto t0 = Clock::now();
  try {
    model.internalForcesAndStiffness(from.t, from.x, fint_, A_);
  } catch (const InvertedElementError& e) {
    throw invertedAtStart(e, from.t);
  }
  model.externalForces(tNext, fext_);
  Kv_.noalias() = A_ * from.v;
  model.mass.multiply(from.v, Mv_);
  rhs_ = h * (fext_ - fint_ - model.rayleighMass * Mv_ - (model.rayleighStiffness + h) * Kv_);
  formSystemMatrix(model, h);
  // Constrained dofs reach their prescribed positions at t + h: x + h (v + dv) = target.
  if (!bc.empty()) {
    knownVelocityChange(model, rest_, from, h, tNext, knownDv_);
    bc.eliminate(A_, rhs_, knownDv_);
  }
  timings_.assembly += secondsBetween(t0, Clock::now());

  t0 = Clock::now();
  solver_->setMatrix(A_);
  // The previous steps' velocity changes make a good initial guess for iterative solvers:
  // motion is smooth over one camera frame. A part of a halved step takes its share of the last.
  if (stepDv_.size() != rhs_.size()) {
    dv_ = Eigen::VectorXd::Zero(rhs_.size());
  } else if (h != options_.dt) {
    dv_ = (h / options_.dt) * stepDv_;
  } else if (options_.extrapolateGuess && previousStepDv_.size() == stepDv_.size()) {
    dv_ = 2.0 * stepDv_ - previousStepDv_;
  } else {
    dv_ = stepDv_;
  }
  timings_.lastSolve = solver_->solve(rhs_, dv_);
  ++timings_.linearSolves;
  timings_.solve += secondsBetween(t0, Clock::now());

  const Eigen::VectorXd& x0 = from.x;
  const Eigen::VectorXd& v0 = from.v;
  s.v = v0 + dv_;
  s.x = x0 + h * s.v;

  // Optional Newton iterations on R(v) = M (v - v0) + h (f_int(x0 + h v) + D v - f_ext), until
  // |R| is below the tolerance or the round-off of h f_int; a step still above after
  // newtonIterations of them has failed. The last state is always one whose forces were assembled.
  for (int it = 0; options_.newtonIterations > 0; ++it) {
    t0 = Clock::now();
    model.internalForcesAndStiffness(tNext, s.x, fint_, A_);
    const double floor = h * forceRoundOff(A_, s.x);  // A_ holds K until formSystemMatrix
    Kv_.noalias() = A_ * s.v;
    model.mass.multiply(s.v - v0, Mv_);
    rhs_ = -(Mv_ + h * (fint_ - fext_ + model.rayleighStiffness * Kv_));
    Eigen::VectorXd Mv1;
    model.mass.multiply(s.v, Mv1);
    rhs_ -= h * model.rayleighMass * Mv1;
    if (!bc.empty()) {
      bc.zeroConstrained(rhs_);
      formSystemMatrix(model, h);
      bc.eliminate(A_, rhs_, Eigen::VectorXd::Zero(bc.constrainedDofs().size()));
    } else {
      formSystemMatrix(model, h);
    }
    const double residual = rhs_.norm();
    const double tolerance =
        options_.newtonTolerance * std::max(std::max(h * fext_.norm(), Mv1.norm()), 1e-300);
    timings_.assembly += secondsBetween(t0, Clock::now());
    if (residual <= std::max(tolerance, floor)) break;
    if (it == options_.newtonIterations)
      throw NumericalError(
          fmt::format("Newton did not converge in {} iteration{} (residual {:.3g} N s, tolerance "
                      "{:.3g} N s)",
                      it, it == 1 ? "" : "s", residual, std::max(tolerance, floor)));
    t0 = Clock::now();
    solver_->setMatrix(A_);
    dv_.setZero();
    timings_.lastSolve = solver_->solve(rhs_, dv_);
    ++timings_.linearSolves;
    timings_.solve += secondsBetween(t0, Clock::now());
    s.v += dv_;
    s.x = x0 + h * s.v;
  }
  s.t = tNext;
  checkEndState(model, s, options_.newtonIterations > 0);
}

void ImplicitEuler::checkEndState(const MechanicalModel& model, const MechanicalState& s,
                                  bool forcesSeenThere) const {
  if (!s.x.allFinite() || !s.v.allFinite())
    throw NumericalError("non-finite state (the time step is too large for the motion)");
  // A state the Newton loop assembled was checked there, every tet.
  if (!forcesSeenThere) model.elasticity.requireNoInverted(s.x);
}

void ImplicitEuler::stepWithTangent(const MechanicalModel& model, MechanicalState& s,
                                    const FrozenTangent& tangent, bool singlePrecision) {
  const auto start = Clock::now();
  timings_ = {};
  const double h = options_.dt;
  if (tangent.dt() != h)
    throw InputError(
        fmt::format("implicit Euler: the shared tangent was built for dt = {:.6g} s, "
                    "this integrator steps {:.6g} s",
                    tangent.dt(), h));
  const MechanicalState from = s;
  try {
    attemptWithTangent(model, s, tangent, singlePrecision);
  } catch (const StepFailure&) {
    throw;
  } catch (const NumericalError& e) {
    // The shared tangent is the W of a step of dt only: the halves take their own.
    s = from;
    halve(model, s, h, e);
  }
  timings_.total = secondsBetween(start, Clock::now());
}

void ImplicitEuler::attemptWithTangent(const MechanicalModel& model, MechanicalState& s,
                                       const FrozenTangent& tangent, bool singlePrecision) {
  const double h = options_.dt;
  const double tNext = s.t + h;
  const DirichletConditions& bc = model.dirichlet;

  auto t0 = Clock::now();
  try {
    model.internalForces(s.t, s.x, fint_);
  } catch (const InvertedElementError& e) {
    throw invertedAtStart(e, s.t);
  }
  model.externalForces(tNext, fext_);
  Kv_.noalias() = tangent.stiffness() * s.v;
  // This state's own spring stiffness in place of the tangent's: blocks D_s = H_s' - H_s.
  const Eigen::MatrixXd D = tangent.springChange(model, s.x, s.t);
  if (D.size() > 0)
    springScatterAdd(model, blockDiagonalTimes(D, springGather(model, s.v, false)), false, Kv_);
  model.mass.multiply(s.v, Mv_);
  rhs_ = h * (fext_ - fint_ - model.rayleighMass * Mv_ - (model.rayleighStiffness + h) * Kv_);
  if (!bc.empty()) {
    knownVelocityChange(model, rest_, s, h, tNext, knownDv_);
    if (D.size() > 0 && knownDv_.any()) {  // the springs' share of the known columns
      Eigen::VectorXd known = Eigen::VectorXd::Zero(rhs_.size());
      for (Eigen::Index k = 0; k < knownDv_.size(); ++k)
        known(bc.constrainedDofs()[k]) = knownDv_(k);
      tangent.moveKnownSpringColumns(model, D, known, rhs_);
    }
    bc.eliminateRightHandSide(tangent.systemMatrix(), rhs_, knownDv_);
  }
  timings_.assembly += secondsBetween(t0, Clock::now());

  t0 = Clock::now();
  tangent.solve(D, rhs_, dv_, factorWork_, singlePrecision);
  ++timings_.linearSolves;
  timings_.lastSolve = {};
  timings_.solve += secondsBetween(t0, Clock::now());

  s.v += dv_;
  s.x += h * s.v;
  s.t = tNext;
  checkEndState(model, s, false);
}

}  // namespace bcassim
