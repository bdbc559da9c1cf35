#include "bcassim/mechanics/StaticSolver.h"

#include "bcassim/Error.h"

namespace bcassim {

StaticSolver::StaticSolver(const MechanicalModel& model, std::unique_ptr<LinearSolver> solver,
                           StaticOptions options)
    : solver_(std::move(solver)), options_(options), K_(model.pattern->emptyMatrix()) {
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

StaticReport StaticSolver::solve(const MechanicalModel& model, double t, Eigen::VectorXd& x) {
  StaticReport report;
  const Eigen::VectorXd rest = model.restPositions();
  const DirichletConditions& bc = model.dirichlet;
  Eigen::VectorXd fextFull, fext, fint, g, dx(x.size()), trial;
  model.externalForces(t, fextFull);
  const Eigen::VectorXd targetFull = bc.empty() ? Eigen::VectorXd() : bc.targetPositions(rest, t);
  const Eigen::VectorXd start = x;

  for (int stepIndex = 1; stepIndex <= options_.loadSteps; ++stepIndex) {
    const double lambda = static_cast<double>(stepIndex) / options_.loadSteps;
    fext = lambda * fextFull;
    for (size_t k = 0; k < bc.constrainedDofs().size(); ++k) {
      const int d = bc.constrainedDofs()[k];
      x(d) = start(d) + lambda * (targetFull(k) - start(d));
    }
    auto potential = [&](const Eigen::VectorXd& y) {
      return model.storedEnergy(t, y) - fext.dot(y - rest);
    };
    double reference = 0;
    for (int it = 0; it < options_.maxIterations; ++it) {
      model.internalForcesAndStiffness(t, x, fint, K_);
      g = fint - fext;
      bc.zeroConstrained(g);
      if (it == 0) reference = std::max({fext.norm(), fint.norm(), 1e-300});
      report.residualNorm = g.norm();
      if (!std::isfinite(report.residualNorm))
        throw NumericalError("static solver: non-finite residual (an element inverted?)");
      if (report.residualNorm <= options_.relativeTolerance * reference) break;
      ++report.iterations;
      Eigen::VectorXd rhs = -g;
      bc.eliminate(K_, rhs, Eigen::VectorXd::Zero(bc.constrainedDofs().size()));
      factorizeRegularized(model);
      dx.setZero();
      solver_->solve(rhs, dx);
      // Backtracking (Armijo) on the total potential; the Newton step is a descent direction
      // while K is positive definite.
      const double p0 = potential(x);
      const double slope = g.dot(dx);
      const Eigen::Index inverted0 = model.elasticity.countInverted(x);
      double alpha = 1.0;
      for (int ls = 0; ls < 30; ++ls) {
        trial = x + alpha * dx;
        const double p = potential(trial);
        // Round-off in the energy sum allows a relative slack, else converged steps would be
        // refused. Steps that invert elements are refused too: StVK's energy is not coercive, so
        // inverting a tet can lower it and Newton would otherwise walk into a collapsed state.
        if (std::isfinite(p) &&
            p <= p0 + 1e-4 * alpha * std::min(slope, 0.0) + 1e-12 * std::abs(p0) &&
            model.elasticity.countInverted(trial) <= inverted0)
          break;
        alpha *= 0.5;
      }
      x = trial;
    }
  }
  model.internalForces(t, x, fint);
  g = fint - fext;
  bc.zeroConstrained(g);
  report.residualNorm = g.norm();
  report.converged =
      report.residualNorm <=
      std::max(options_.relativeTolerance * std::max(fext.norm(), fint.norm()), 1e-12);
  return report;
}

}  // namespace bcassim
