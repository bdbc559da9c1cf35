#include "bcassim/app/MechanicalForecastModel.h"

#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"

namespace bcassim {

MechanicalForecastModel::MechanicalForecastModel(
    const MechanicalModel& model, ImplicitEulerOptions integrator,
    std::vector<MappedPoint> observed, std::vector<ModelParameterTarget> parameters,
    const MechanicalState& initial, ForecastModelOptions options, int worker,
    std::shared_ptr<SharedFactorization> shared)
    : model_(model),
      integrator_(model_, makeLinearSolver(options.solver, options.refresh), integrator),
      observed_(std::move(observed)),
      parameters_(std::move(parameters)),
      reference_(initial),
      options_(options),
      worker_(worker),
      shared_(options.shareFactorization ? std::move(shared) : nullptr) {}

Eigen::Index MechanicalForecastModel::stateSize() const {
  const Eigen::Index n = 3 * model_.mesh->numNodes();
  return (options_.layout.positions ? n : 0) + (options_.layout.velocities ? n : 0);
}

Eigen::VectorXd MechanicalForecastModel::packState(const MechanicalState& s) const {
  Eigen::VectorXd out(stateSize());
  Eigen::Index at = 0;
  if (options_.layout.positions) {
    out.segment(at, s.x.size()) = s.x;
    at += s.x.size();
  }
  if (options_.layout.velocities) out.segment(at, s.v.size()) = s.v;
  return out;
}

void MechanicalForecastModel::unpackState(const Eigen::VectorXd& state, MechanicalState& s) const {
  Eigen::Index at = 0;
  if (options_.layout.positions) {
    s.x = state.segment(at, s.x.size());
    at += s.x.size();
  }
  if (options_.layout.velocities) s.v = state.segment(at, s.v.size());
}

void MechanicalForecastModel::setParameters(const Eigen::VectorXd& params) {
  for (size_t i = 0; i < parameters_.size(); ++i) applyParameter(parameters_[i], params(i), model_);
}

void MechanicalForecastModel::observe(const MechanicalState& s, Eigen::VectorXd& predicted) const {
  predicted.resize(observationSize());
  for (size_t i = 0; i < observed_.size(); ++i)
    predicted.segment<3>(3 * i) = interpolate(observed_[i], *model_.mesh, s.x);
}

void MechanicalForecastModel::forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                                       Eigen::VectorXd& newState, Eigen::VectorXd& predicted) {
  work_ = reference_;
  unpackState(state, work_);
  setParameters(params);
  // Thesis Alg. 4/5: worker 0 refreshes the factorisation when its policy says so; the others
  // precondition their PCG with the one it published (SharedFactorization).
  auto* reuse = dynamic_cast<FactorizedPcgSolver*>(&integrator_.linearSolver());
  if (shared_ && reuse && worker_ != 0 && shared_->factor) reuse->shareFactor(shared_->factor);
  integrator_.step(model_, work_);
  if (shared_ && reuse && worker_ == 0) {
    shared_->next = reuse->factor();
    if (shared_->withinStep) shared_->factor = shared_->next;
  }
  newState = packState(work_);
  observe(work_, predicted);
}

void MechanicalForecastModel::endStep(const Eigen::VectorXd& state, const Eigen::VectorXd& params) {
  if (shared_ && worker_ == 0) shared_->factor = shared_->next;
  setParameters(params);
  if (options_.layout.positions && options_.layout.velocities) {
    unpackState(state, reference_);
    reference_.t += integrator_.options().dt;
    return;
  }
  // Without the full mechanical state in the filter, the mean trajectory is continued by one more
  // step with the analysed parameters, then corrected by whatever part the filter does carry.
  integrator_.step(model_, reference_);
  unpackState(state, reference_);
}

Eigen::MatrixX3d MechanicalForecastModel::positionsOf(const std::vector<MappedPoint>& points) const {
  Eigen::MatrixX3d out(points.size(), 3);
  for (size_t i = 0; i < points.size(); ++i)
    out.row(i) = interpolate(points[i], *model_.mesh, reference_.x).transpose();
  return out;
}

}  // namespace bcassim
