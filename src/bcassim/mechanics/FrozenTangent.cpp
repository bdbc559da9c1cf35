#include "bcassim/mechanics/FrozenTangent.h"

#include <chrono>

namespace bcassim {

std::shared_ptr<const FrozenTangent> FrozenTangent::build(const MechanicalModel& model,
                                                          const MechanicalState& state, double dt,
                                                          const CholeskyFactor* analysis) {
  const auto start = std::chrono::steady_clock::now();
  auto t = std::make_shared<FrozenTangent>();
  t->dt_ = dt;
  Eigen::VectorXd f;
  model.internalForcesAndStiffness(state.t, state.x, f, t->K_);
  t->A_ = t->K_;
  t->A_.coeffs() *= dt * model.rayleighStiffness + dt * dt;
  model.mass.addTo(*model.pattern, 1.0 + dt * model.rayleighMass, t->A_);
  SparseMatrix eliminated = t->A_;
  model.dirichlet.eliminateMatrix(eliminated);
  if (analysis != nullptr && analysis->isAnalyzed() && analysis->matchesPattern(eliminated)) {
    t->factor_ = analysis->cloneAnalysis();
  } else {
    t->factor_ = std::make_shared<CholeskyFactor>();
    t->factor_->analyzePattern(eliminated);
  }
  t->factor_->factorize(eliminated);
  t->buildSeconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return t;
}

}  // namespace bcassim
