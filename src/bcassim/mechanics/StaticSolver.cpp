#include "bcassim/mechanics/StaticSolver.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/mechanics/InvertedElementError.h"
#include "bcassim/mechanics/ResidualFloor.h"
#include "bcassim/mechanics/solvers/CholmodSolver.h"

namespace bcassim {

namespace {
constexpr const char* kIntegrator = "static solver";
// Steps a chord iteration's Anderson mixing combines (AndersonMixing).
constexpr int kChordMixingDepth = 5;
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

int chordStepsToGo(const StaticReport& report) {
  constexpr int kUnknown = std::numeric_limits<int>::max();
  if (report.iterations < 2 || !(report.tolerance > 0) ||
      !(report.residualNorm > report.tolerance) || !(report.initialResidualNorm > 0))
    return kUnknown;
  const double rate =
      std::log(report.residualNorm / report.initialResidualNorm) / report.iterations;
  if (!(rate < 0)) return kUnknown;
  const double steps = std::ceil(std::log(report.tolerance / report.residualNorm) / rate);
  return steps < kUnknown ? static_cast<int>(steps) : kUnknown;
}

StaticSolver::StaticSolver(const MechanicalModel& model, std::unique_ptr<LinearSolver> solver,
                           StaticOptions options)
    : solver_(std::move(solver)),
      options_(options),
      K_(model.pattern->emptyMatrix()),
      chordMixing_(kChordMixingDepth) {
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
  factorizedUnshifted_ = false;
  for (int attempt = 0;; ++attempt) {
    try {
      solver_->setMatrix(K_);
      factorizedUnshifted_ = shift == 0.0;
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

void StaticSolver::warmUp(const MechanicalModel& model, double t, const Eigen::VectorXd& x) {
  Eigen::VectorXd fint;
  try {
    newtonTangentReady_ = false;
    model.internalForcesAndStiffness(t, x, fint, K_);
    model.dirichlet.eliminateMatrix(K_);
    solver_->setMatrix(K_);
  } catch (const NumericalError&) {
  }
}

StaticReport StaticSolver::solve(const MechanicalModel& model, double t, Eigen::VectorXd& x) {
  newtonTangentReady_ = false;
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
  newtonTangentReady_ = report.iterations > 0 && factorizedUnshifted_;
  return report;
}

std::shared_ptr<const FrozenTangent> StaticSolver::newtonTangent(const MechanicalModel& model,
                                                                 const MechanicalState& at) const {
  const auto* cholmod = dynamic_cast<const CholmodSolver*>(solver_.get());
  if (!newtonTangentReady_ || !cholmod || !cholmod->factor()->isFactorized()) return nullptr;
  return FrozenTangent::fromFactor(model, at, K_, cholmod->factor());
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
  // The potential and the inverted count at x, kept from the line search that accepted x (the
  // loads do not change within this call): each iteration after the first saves a pass over the
  // elements for each.
  std::optional<double> potentialAtX;
  std::optional<Eigen::Index> invertedAtX;
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
    const double p0 = potentialAtX ? *potentialAtX : potential(x);
    const double slope = run.g.dot(run.dx);
    const Eigen::Index inverted0 = invertedAtX ? *invertedAtX : model.elasticity.countInverted(x);
    double alpha = 1.0;
    bool accepted = false;
    for (int ls = 0; ls < 30 && !accepted; ++ls) {
      run.trial = x + alpha * run.dx;
      const double p = potential(run.trial);
      // Round-off in the energy sum allows a relative slack, else converged steps would be
      // refused. Steps that invert elements are refused too: StVK's energy is not coercive, so
      // inverting a tet can lower it and Newton would otherwise walk into a collapsed state.
      accepted =
          std::isfinite(p) && p <= p0 + 1e-4 * alpha * std::min(slope, 0.0) + 1e-12 * std::abs(p0);
      if (accepted) {
        const Eigen::Index inverted = model.elasticity.countInverted(run.trial);
        accepted = inverted <= inverted0;
        if (accepted) {
          potentialAtX = p;
          invertedAtX = inverted;
        }
      }
      if (!accepted) alpha *= 0.5;
    }
    if (!accepted)
      throw NumericalError(fmt::format(
          "the line search of Newton iteration {} found no acceptable step (residual {:.3g} N)",
          it + 1, report.residualNorm));
    x = run.trial;
  }
}

StaticReport StaticSolver::chordSolve(const MechanicalModel& model, double t, Eigen::VectorXd& x,
                                      const FrozenTangent& tangent, int maxIterations,
                                      bool singlePrecision, int threads) {
  return chordIterations(model, t, x, tangent, maxIterations, singlePrecision, threads, false);
}

StaticReport StaticSolver::continueChord(const MechanicalModel& model, double t, Eigen::VectorXd& x,
                                         const FrozenTangent& tangent, int maxIterations,
                                         bool singlePrecision, int threads) {
  return chordIterations(model, t, x, tangent, maxIterations, singlePrecision, threads, true);
}

StaticReport StaticSolver::chordIterations(const MechanicalModel& model, double t,
                                           Eigen::VectorXd& x, const FrozenTangent& tangent,
                                           int maxIterations, bool singlePrecision, int threads,
                                           bool continuing) {
  if (!tangent.isStatic())
    throw std::invalid_argument("StaticSolver::chordSolve: needs a static tangent (K, not W)");
  // The split kernels' threads are kept between calls: a model's sigma point (serial) and its
  // mean (split) alternate every frame.
  if (threads > 0 && (!chordChunks_ || chordChunks_->threads() != threads)) {
    chordSplitWork_.setThreads(threads);
    chordChunks_ = std::make_unique<ChunkedForces>(threads);
  }
  CholeskyFactor::Workspace& work = threads > 0 ? chordSplitWork_ : chordWork_;
  const DirichletConditions& bc = model.dirichlet;
  const auto& fixed = bc.constrainedDofs();
  StaticReport report;
  model.externalForces(t, chordFext_);
  const Eigen::VectorXd rest = model.restPositions();
  const Eigen::VectorXd target = bc.empty() ? Eigen::VectorXd() : bc.targetPositions(rest, t);
  // The residual f_ext - f_int at y (constrained entries zero) into chordRhs_, the prescribed
  // motion still to make into chordKnown_; its norm.
  const auto residualAt = [&](const Eigen::VectorXd& y) {
    if (threads > 0)
      model.internalForces(t, y, chordFint_, *chordChunks_);
    else
      model.internalForces(t, y, chordFint_);
    chordRhs_ = chordFext_ - chordFint_;
    bc.zeroConstrained(chordRhs_);
    chordKnown_.resize(static_cast<Eigen::Index>(fixed.size()));
    for (size_t k = 0; k < fixed.size(); ++k)
      chordKnown_(static_cast<Eigen::Index>(k)) =
          target(static_cast<Eigen::Index>(k)) - y(fixed[k]);
    return chordRhs_.norm();
  };
  const auto placeExactly = [&](Eigen::VectorXd& y) {  // not up to round-off
    for (size_t k = 0; k < fixed.size(); ++k) y(fixed[k]) = target(static_cast<Eigen::Index>(k));
  };
  // The total potential energy at y (J), whose gradient is -(f_ext - f_int).
  const auto potentialAt = [&](const Eigen::VectorXd& y) {
    return model.storedEnergy(t, y) - chordFext_.dot(y - rest);
  };
  double norm = residualAt(x);
  double potential = std::numeric_limits<double>::quiet_NaN();  // at x, once needed
  report.initialResidualNorm = norm;
  const double reference = std::max({chordFext_.norm(), chordFint_.norm(), 1e-300});
  // A continuation goes on with the last call's mixing history (its steps are of the same map).
  if (!continuing) chordMixing_.clear();
  AndersonMixing& mixing = chordMixing_;
  for (;;) {
    report.residualNorm = norm;
    if (!std::isfinite(norm))
      throw NumericalError(
          fmt::format("non-finite residual at chord iteration {}", report.iterations));
    const double tolerance = std::max(options_.relativeTolerance * reference,
                                      forceRoundOff(tangent.stiffnessDiagonalNorm(), x));
    report.tolerance = tolerance;
    const bool placed = !chordKnown_.any();
    if (norm <= tolerance && placed) {
      report.converged = true;
      break;
    }
    if (report.iterations == maxIterations) break;
    ++report.iterations;
    chordG_ = chordRhs_;  // f_ext - f_int on the free dofs, before elimination
    const Eigen::MatrixXd D = tangent.springChange(model, x, t);
    if (!bc.empty()) {
      if (D.size() > 0 && !placed) {
        Eigen::VectorXd known = Eigen::VectorXd::Zero(x.size());
        for (size_t k = 0; k < fixed.size(); ++k)
          known(fixed[k]) = chordKnown_(static_cast<Eigen::Index>(k));
        tangent.moveKnownSpringColumns(model, D, known, chordRhs_);
      }
      bc.eliminateRightHandSide(tangent.systemMatrix(), chordRhs_, chordKnown_);
    }
    tangent.solve(D, chordRhs_, chordDx_, work, singlePrecision);
    if (maxIterations == 1) {
      // One linearised step (a sigma point about its mean) needs no residual after it. Longer
      // runs evaluate their last step as any other: a blind last step could leave a caller that
      // finishes by Newton a start far worse than the iterate before it, and say nothing of it.
      x += chordDx_;
      placeExactly(x);
      model.elasticity.requireNoInverted(x);
      break;
    }
    // The step that moves the prescribed dofs is taken whole. After it, Anderson-mixed steps are
    // kept where they lower the residual; where they do not, the total potential energy decides
    // (a nearly incompressible organ under a tool's point load can raise the residual along a
    // good step): the mixed step or the plain chord step (a descent direction, K0 being positive
    // definite), halved down to an eighth, kept at Armijo's sufficient decrease. An inverted
    // element counts as no decrease.
    if (!placed) mixing.clear();
    const bool mixed = placed && mixing.willMix();
    const Eigen::VectorXd step = placed ? mixing.step(x, chordDx_) : chordDx_;
    const auto tryStep = [&](const Eigen::VectorXd& dx) {
      chordTrial_ = x + dx;
      placeExactly(chordTrial_);
    };
    tryStep(step);
    double trialNorm = std::numeric_limits<double>::infinity();
    try {
      trialNorm = residualAt(chordTrial_);
    } catch (const InvertedElementError&) {
      if (!placed) throw;
    }
    double trialPotential = std::numeric_limits<double>::quiet_NaN();
    if (!(trialNorm < norm) && placed) {
      mixing.clear();
      if (std::isnan(potential)) potential = potentialAt(x);
      bool accepted = false;
      const auto armijo = [&](double slope) {
        if (!(slope < 0) || model.elasticity.countInverted(chordTrial_) > 0) return false;
        trialPotential = potentialAt(chordTrial_);
        return std::isfinite(trialPotential) &&
               trialPotential <= potential + 1e-4 * slope + 1e-12 * std::abs(potential);
      };
      if (std::isfinite(trialNorm)) accepted = armijo(-chordG_.dot(step));
      for (double alpha = mixed ? 1.0 : 0.5; !accepted && alpha >= 0.125; alpha *= 0.5) {
        tryStep(alpha * chordDx_);
        accepted = armijo(-alpha * chordG_.dot(chordDx_));
      }
      if (!accepted) {
        residualAt(x);  // chordRhs_ and the report describe x again
        break;
      }
      trialNorm = residualAt(chordTrial_);
    }
    if (!std::isfinite(trialNorm)) model.elasticity.requireNoInverted(chordTrial_);
    x.swap(chordTrial_);
    norm = trialNorm;
    potential = trialPotential;
  }
  if (report.converged) equilibriumLoad_ = chordFext_;
  return report;
}

}  // namespace bcassim
