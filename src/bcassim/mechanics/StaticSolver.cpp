#include "bcassim/mechanics/StaticSolver.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/mechanics/ResidualFloor.h"

namespace bcassim {

namespace {
constexpr const char* kIntegrator = "static solver";
}  // namespace

// One solve(): the model, the time, the solution being built and the two ends of the load path.
struct StaticSolver::Increments {
  const MechanicalModel& model;
  double t;
  Eigen::VectorXd& x;
  StaticReport& report;
  Eigen::VectorXd startLoad, fextFull, targetFull, start, rest;
  double nominal;  // a load step's increment of lambda
  Eigen::VectorXd fext, fint, g, dx, trial;
};

StaticSolver::StaticSolver(const MechanicalModel& model, std::unique_ptr<LinearSolver> solver,
                           StaticOptions options)
    : solver_(std::move(solver)), options_(options), K_(model.pattern->emptyMatrix()) {
  if (!(options_.minIncrementFraction > 0) || options_.minIncrementFraction > 1)
    throw InputError(
        fmt::format("static solver: the smallest load increment must be a fraction in (0, 1] of a "
                    "load step's, got {:.6g}",
                    options_.minIncrementFraction));
  solver_->analyzePattern(K_);
}

// Far from equilibrium (buckling, strong compression) the tangent of StVK or corotational
// elasticity can be indefinite; shifting its diagonal (Levenberg-style) keeps the Newton step a
// descent direction, and the line search does the rest.
void StaticSolver::factorizeRegularized(const MechanicalModel& model) {
  double shift = 0.0;
  const double scale = K_.diagonal().cwiseAbs().mean();
  for (int attempt = 0;; ++attempt) {
    try {
      solver_->setMatrix(K_);
      return;
    } catch (const NumericalError&) {
      if (attempt == 12) throw;
      const double next = shift == 0.0 ? 1e-6 * scale : 10.0 * shift;
      const auto& bc = model.dirichlet.constrainedDofs();
      Eigen::VectorXd add = Eigen::VectorXd::Constant(K_.rows(), next - shift);
      for (int d : bc) add(d) = 0.0;  // constrained rows stay identity
      for (Eigen::Index d = 0; d < K_.rows(); ++d) K_.coeffRef(d, d) += add(d);
      shift = next;
    }
  }
}

void StaticSolver::continueFrom(const MechanicalModel& model, double t) {
  model.externalForces(t, equilibriumLoad_);
}

StaticReport StaticSolver::solve(const MechanicalModel& model, double t, Eigen::VectorXd& x) {
  StaticReport report;
  Increments run{model, t, x, report};
  run.rest = model.restPositions();
  run.startLoad = equilibriumLoad_;
  model.externalForces(t, run.fextFull);
  const DirichletConditions& bc = model.dirichlet;
  if (!bc.empty()) run.targetFull = bc.targetPositions(run.rest, t);
  run.start = x;
  run.dx.resize(x.size());
  run.nominal = 1.0 / options_.loadSteps;
  for (int stepIndex = 1; stepIndex <= options_.loadSteps; ++stepIndex)
    solveIncrement(run, static_cast<double>(stepIndex - 1) / options_.loadSteps,
                   static_cast<double>(stepIndex) / options_.loadSteps);
  equilibriumLoad_ = run.fext;
  report.converged = true;
  return report;
}

// Newton from the equilibrium at `from` to the one at `to`; if that fails, from `from` to the
// midpoint and on to `to`, each halved again where it fails, down to the smallest increment.
void StaticSolver::solveIncrement(Increments& run, double from, double to) {
  const Eigen::VectorXd x0 = run.x;
  try {
    newton(run, to);
  } catch (const StepFailure&) {
    throw;
  } catch (const NumericalError& e) {
    const double half = 0.5 * (to - from);
    if (half < options_.minIncrementFraction * run.nominal) {
      const double cut = run.nominal / (to - from);
      throw StepFailure(
          kIntegrator, run.t,
          cut > 1.0
              ? fmt::format("{} with the load increment cut to 1/{:.0f} of a load step's "
                            "(time.min_dt)",
                            e.what(), cut)
              : fmt::format("{} (time.min_dt allows no cut of the load increment)", e.what()));
    }
    run.x = x0;
    ++run.report.retries;
    solveIncrement(run, from, from + half);
    solveIncrement(run, from + half, to);
  }
}

// Newton iterations to the equilibrium at load fraction lambda. Throws NumericalError when it is
// not reached (InvertedElementError, LinearSolveError from the assembly and the solve).
void StaticSolver::newton(Increments& run, double lambda) {
  const MechanicalModel& model = run.model;
  const DirichletConditions& bc = model.dirichlet;
  Eigen::VectorXd& x = run.x;
  StaticReport& report = run.report;
  // Loads ramp from the start's (none at first: lambda f_ext(t) exactly, as ever; the last step
  // of a later solve is f_ext(t) exactly too, (1 - 1) f_0 being 0).
  if (run.startLoad.size() == 0)
    run.fext = lambda * run.fextFull;
  else
    run.fext = (1.0 - lambda) * run.startLoad + lambda * run.fextFull;
  for (size_t k = 0; k < bc.constrainedDofs().size(); ++k) {
    const int d = bc.constrainedDofs()[k];
    x(d) = run.start(d) + lambda * (run.targetFull(k) - run.start(d));
  }
  const Eigen::VectorXd& fext = run.fext;
  auto potential = [&](const Eigen::VectorXd& y) {
    return model.storedEnergy(run.t, y) - fext.dot(y - run.rest);
  };
  double reference = 0;
  for (int it = 0;; ++it) {
    model.internalForcesAndStiffness(run.t, x, run.fint, K_);
    run.g = run.fint - fext;
    bc.zeroConstrained(run.g);
    if (it == 0) reference = std::max({fext.norm(), run.fint.norm(), 1e-300});
    report.residualNorm = run.g.norm();
    if (!std::isfinite(report.residualNorm))
      throw NumericalError(fmt::format("non-finite residual at Newton iteration {}", it));
    const double tolerance = std::max(options_.relativeTolerance * reference, forceRoundOff(K_, x));
    if (report.residualNorm <= tolerance) return;
    if (it == options_.maxIterations)
      throw NumericalError(fmt::format(
          "Newton did not converge in {} iteration{} (residual {:.3g} N, tolerance {:.3g} N)", it,
          it == 1 ? "" : "s", report.residualNorm, tolerance));
    ++report.iterations;
    Eigen::VectorXd rhs = -run.g;
    bc.eliminate(K_, rhs, Eigen::VectorXd::Zero(bc.constrainedDofs().size()));
    factorizeRegularized(model);
    run.dx.setZero();
    solver_->solve(rhs, run.dx);
    // Backtracking (Armijo) on the total potential; the Newton step is a descent direction
    // while K is positive definite.
    const double p0 = potential(x);
    const double slope = run.g.dot(run.dx);
    const Eigen::Index inverted0 = model.elasticity.countInverted(x);
    double alpha = 1.0;
    bool accepted = false;
    for (int ls = 0; ls < 30 && !accepted; ++ls) {
      run.trial = x + alpha * run.dx;
      const double p = potential(run.trial);
      // Round-off in the energy sum allows a relative slack, else converged steps would be
      // refused. Steps that invert elements are refused too: StVK's energy is not coercive, so
      // inverting a tet can lower it and Newton would otherwise walk into a collapsed state.
      accepted = std::isfinite(p) &&
                 p <= p0 + 1e-4 * alpha * std::min(slope, 0.0) + 1e-12 * std::abs(p0) &&
                 model.elasticity.countInverted(run.trial) <= inverted0;
      if (!accepted) alpha *= 0.5;
    }
    if (!accepted)
      throw NumericalError(fmt::format(
          "the line search of Newton iteration {} found no acceptable step (residual {:.3g} N)",
          it + 1, report.residualNorm));
    x = run.trial;
  }
}

}  // namespace bcassim
