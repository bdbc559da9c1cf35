#include "bcassim/coupling/ParameterForwardRun.h"

#include "bcassim/mechanics/solvers/LinearSolverFactory.h"

namespace bcassim {

ParameterForwardRun::ParameterForwardRun(const Scene& scene,
                                         const std::vector<EstimatedParameter>& parameters,
                                         const Eigen::VectorXd& values)
    : model_(scene.model), dt_(scene.dt()) {
  for (size_t i = 0; i < parameters.size(); ++i)
    applyParameter(parameters[i].target, values(static_cast<Eigen::Index>(i)), model_);
  state_ = model_.restState();
  if (scene.integrator == IntegratorKind::Static)
    statics_ = std::make_unique<StaticSolver>(
        model_, makeLinearSolver(scene.solver.type, scene.solver.policy), scene.statics);
  else
    integrator_ = std::make_unique<ImplicitEuler>(
        model_, makeLinearSolver(scene.solver.type, scene.solver.policy), scene.implicitEuler);
}

void ParameterForwardRun::step() {
  if (statics_)
    statics_->solve(model_, (steps_ + 1) * dt_, state_.x);
  else if (tangent_)
    integrator_->stepWithTangent(model_, state_, *tangent_, singlePrecision_);
  else
    integrator_->step(model_, state_);
  ++steps_;
  state_.t = steps_ * dt_;  // as the simulate runner: no drift from summing dt
}

void ParameterForwardRun::setValues(const std::vector<EstimatedParameter>& parameters,
                                    const Eigen::VectorXd& values) {
  for (size_t i = 0; i < parameters.size(); ++i)
    applyParameter(parameters[i].target, values(static_cast<Eigen::Index>(i)), model_);
}

void ParameterForwardRun::restore(const MechanicalState& state, int steps) {
  state_ = state;
  steps_ = steps;
  if (statics_) statics_->continueFrom(model_, state_.t);
}

Eigen::MatrixX3d ParameterForwardRun::positionsOf(const std::vector<MappedPoint>& points) const {
  Eigen::MatrixX3d out(points.size(), 3);
  for (size_t i = 0; i < points.size(); ++i)
    out.row(i) = interpolate(points[i], *model_.mesh, state_.x).transpose();
  return out;
}

}  // namespace bcassim
