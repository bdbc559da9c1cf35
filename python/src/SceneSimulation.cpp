#include "SceneSimulation.h"

#include <fmt/format.h>

#include "bcassim/Error.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/BarycentricMap.h"

namespace bcassim::python {

SceneSimulation::SceneSimulation(const Scene& scene)
    : scene_(scene), model_(scene.model), state_(model_.restState()) {
  auto solver = makeLinearSolver(scene.solver.type, scene.solver.policy);
  if (scene.integrator == IntegratorKind::Static)
    equilibrium_ = std::make_unique<StaticSolver>(model_, std::move(solver), scene.statics);
  else
    dynamics_ = std::make_unique<ImplicitEuler>(model_, std::move(solver), scene.implicitEuler);
}

void SceneSimulation::step() {
  const int next = steps_ + 1;
  try {
    if (equilibrium_) {
      state_.t = next * scene_.dt();
      equilibrium_->solve(model_, state_.t, state_.x);
    } else {
      dynamics_->step(model_, state_);
      state_.t = next * scene_.dt();  // no drift from summing dt
    }
  } catch (const NumericalError& e) {
    throw NumericalError(fmt::format("{}: step {} (t = {:g} s): {}", scene_.sourceFile, next,
                                     next * scene_.dt(), e.what()));
  }
  steps_ = next;
}

Eigen::MatrixX3d SceneSimulation::pointPositions(const MarkerSet& points) const {
  Eigen::MatrixX3d p(points.points.size(), 3);
  for (size_t i = 0; i < points.points.size(); ++i)
    p.row(static_cast<Eigen::Index>(i)) =
        interpolate(points.points[i], *model_.mesh, state_.x).transpose();
  return p;
}

}  // namespace bcassim::python
