#include "bcassim/mechanics/ImplicitEuler.h"

#include <fmt/format.h>

#include <Eigen/LU>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/mechanics/ImplicitEulerSystem.h"

namespace bcassim {
namespace {
// blockdiag(D_0, D_1, ...) v for D stacked as (3k x 3) blocks.
Eigen::VectorXd blockDiagonalTimes(const Eigen::MatrixXd& D, const Eigen::VectorXd& v) {
  Eigen::VectorXd out(v.size());
  for (Eigen::Index b = 0; b < D.rows(); b += 3)
    out.segment<3>(b) = D.middleRows<3>(b) * v.segment<3>(b);
  return out;
}
}  // namespace

ImplicitEuler::ImplicitEuler(const MechanicalModel& model, std::unique_ptr<LinearSolver> solver,
                             ImplicitEulerOptions options)
    : solver_(std::move(solver)), options_(options), A_(model.pattern->emptyMatrix()) {
  if (!(options_.dt > 0)) throw InputError("implicit Euler: dt must be positive (s)");
  solver_->analyzePattern(A_);
  rest_ = model.restPositions();
}

void ImplicitEuler::formSystemMatrix(const MechanicalModel& model) {
  stiffnessToImplicitEulerMatrix(model, options_.dt, A_);
}

void ImplicitEuler::step(const MechanicalModel& model, MechanicalState& s) {
  const auto start = Clock::now();
  timings_ = {};
  const double h = options_.dt;
  const double tNext = s.t + h;
  const DirichletConditions& bc = model.dirichlet;

  // Eq. 2.16, linearised at the current state.
  auto t0 = Clock::now();
  model.internalForcesAndStiffness(s.t, s.x, fint_, A_);
  model.externalForces(tNext, fext_);
  Kv_.noalias() = A_ * s.v;
  model.mass.multiply(s.v, Mv_);
  rhs_ = h * (fext_ - fint_ - model.rayleighMass * Mv_ - (model.rayleighStiffness + h) * Kv_);
  formSystemMatrix(model);
  // Constrained dofs reach their prescribed positions at t + dt: x + dt (v + dv) = target.
  if (!bc.empty()) {
    knownVelocityChange(model, rest_, s, h, tNext, knownDv_);
    bc.eliminate(A_, rhs_, knownDv_);
  }
  timings_.assembly += secondsBetween(t0, Clock::now());

  t0 = Clock::now();
  solver_->setMatrix(A_);
  // The previous steps' velocity changes make a good initial guess for iterative solvers:
  // motion is smooth over one camera frame.
  if (stepDv_.size() != rhs_.size()) {
    dv_ = Eigen::VectorXd::Zero(rhs_.size());
  } else if (options_.extrapolateGuess && previousStepDv_.size() == stepDv_.size()) {
    dv_ = 2.0 * stepDv_ - previousStepDv_;
  } else {
    dv_ = stepDv_;
  }
  timings_.lastSolve = solver_->solve(rhs_, dv_);
  ++timings_.linearSolves;
  timings_.solve += secondsBetween(t0, Clock::now());

  const Eigen::VectorXd x0 = s.x, v0 = s.v;
  s.v = v0 + dv_;
  s.x = x0 + h * s.v;

  // Optional Newton iterations on R(v) = M (v - v0) + h (f_int(x0 + h v) + D v - f_ext).
  for (int it = 0; it < options_.newtonIterations; ++it) {
    t0 = Clock::now();
    model.internalForcesAndStiffness(tNext, s.x, fint_, A_);
    Kv_.noalias() = A_ * s.v;
    model.mass.multiply(s.v - v0, Mv_);
    rhs_ = -(Mv_ + h * (fint_ - fext_ + model.rayleighStiffness * Kv_));
    Eigen::VectorXd Mv1;
    model.mass.multiply(s.v, Mv1);
    rhs_ -= h * model.rayleighMass * Mv1;
    if (!bc.empty()) {
      bc.zeroConstrained(rhs_);
      formSystemMatrix(model);
      bc.eliminate(A_, rhs_, Eigen::VectorXd::Zero(bc.constrainedDofs().size()));
    } else {
      formSystemMatrix(model);
    }
    const double residual = rhs_.norm();
    const double reference = std::max(h * fext_.norm(), Mv1.norm());
    timings_.assembly += secondsBetween(t0, Clock::now());
    if (residual <= options_.newtonTolerance * std::max(reference, 1e-300)) break;
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
  checkFinite(model, s);
  previousStepDv_.swap(stepDv_);
  stepDv_ = s.v - v0;
  timings_.total = secondsBetween(start, Clock::now());
}

void ImplicitEuler::checkFinite(const MechanicalModel& model, const MechanicalState& s) const {
  if (!s.x.allFinite() || !s.v.allFinite())
    throw NumericalError(
        fmt::format("implicit Euler: non-finite state at t = {:.6g} s (time step "
                    "too large, or an element inverted: {} tets)",
                    s.t, model.elasticity.lastInvertedCount()));
}

void ImplicitEuler::stepWithTangent(const MechanicalModel& model, MechanicalState& s,
                                    const FrozenTangent& tangent) {
  const auto start = Clock::now();
  timings_ = {};
  const double h = options_.dt;
  if (tangent.dt() != h)
    throw InputError(
        fmt::format("implicit Euler: the shared tangent was built for dt = {:.6g} s, "
                    "this integrator steps {:.6g} s",
                    tangent.dt(), h));
  const double tNext = s.t + h;
  const DirichletConditions& bc = model.dirichlet;

  auto t0 = Clock::now();
  model.internalForces(s.t, s.x, fint_);
  model.externalForces(tNext, fext_);
  Kv_.noalias() = tangent.stiffness() * s.v;
  // This state's own spring stiffness in place of the tangent's: blocks D_s = H_s' - H_s.
  const bool correct = tangent.correctsSprings();
  Eigen::MatrixXd D;
  if (correct) {
    const size_t springs = tangent.springBlocks().size();
    D = Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(springs), 3);
    for (size_t k = 0; k < springs; ++k)
      D.block<3, 3>(3 * static_cast<Eigen::Index>(k), 0) =
          model.springs.attachmentStiffness(*model.mesh, s.x, s.t, k) - tangent.springBlocks()[k];
    springScatterAdd(model, blockDiagonalTimes(D, springGather(model, s.v, false)), false, Kv_);
  }
  model.mass.multiply(s.v, Mv_);
  rhs_ = h * (fext_ - fint_ - model.rayleighMass * Mv_ - (model.rayleighStiffness + h) * Kv_);
  const double c = tangent.stiffnessScale();
  if (!bc.empty()) {
    knownVelocityChange(model, rest_, s, h, tNext, knownDv_);
    if (correct && knownDv_.any()) {  // the springs' share of the known columns
      Eigen::VectorXd known = Eigen::VectorXd::Zero(rhs_.size()), moved = known;
      for (Eigen::Index k = 0; k < knownDv_.size(); ++k)
        known(bc.constrainedDofs()[k]) = knownDv_(k);
      springScatterAdd(model, blockDiagonalTimes(D, springGather(model, known, false)), false,
                       moved);
      rhs_ -= c * moved;
    }
    bc.eliminateRightHandSide(tangent.systemMatrix(), rhs_, knownDv_);
  }
  timings_.assembly += secondsBetween(t0, Clock::now());

  t0 = Clock::now();
  tangent.factor().solve(rhs_, dv_, factorWork_);
  if (correct && D.any()) {
    // Woodbury (FrozenTangent::springSolutions): dv -= Z (I + c D G)^-1 c D U^T dv.
    const Eigen::MatrixXd& G = tangent.springGram();
    Eigen::MatrixXd system = Eigen::MatrixXd::Identity(G.rows(), G.cols());
    for (Eigen::Index b = 0; b < D.rows(); b += 3)
      system.middleRows<3>(b) += c * D.middleRows<3>(b) * G.middleRows<3>(b);
    const Eigen::VectorXd w =
        system.partialPivLu().solve(c * blockDiagonalTimes(D, springGather(model, dv_, true)));
    dv_.noalias() -= tangent.springSolutions() * w;
  }
  ++timings_.linearSolves;
  timings_.lastSolve = {};
  timings_.solve += secondsBetween(t0, Clock::now());

  s.v += dv_;
  s.x += h * s.v;
  s.t = tNext;
  checkFinite(model, s);
  timings_.total = secondsBetween(start, Clock::now());
}

}  // namespace bcassim
