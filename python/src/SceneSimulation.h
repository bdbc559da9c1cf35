// A scene's model advanced one step at a time from Python, as `bcassim simulate` advances it but
// without its files: the integrator the scene asks for (implicit Euler or static), its solver,
// and the state (positions m, velocities m/s, time s).
#pragma once
#include <memory>

#include "bcassim/mechanics/ImplicitEuler.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/scene/Scene.h"

namespace bcassim::python {

class SceneSimulation {
 public:
  // Copies the scene's model (changing the scene afterwards does not change this run).
  explicit SceneSimulation(const Scene& scene);

  // One time step dt; throws NumericalError (StepFailure) "step N (t = T s): ..." when the step
  // fails even when cut down to the scene's minimal step.
  void step();

  const MechanicalState& state() const { return state_; }
  int stepsDone() const { return steps_; }
  const MechanicalModel& model() const { return model_; }
  // Positions (m, #points x 3) of the scene's markers, validation points or hidden points now.
  Eigen::MatrixX3d pointPositions(const MarkerSet& points) const;
  const Scene& scene() const { return scene_; }

 private:
  Scene scene_;
  MechanicalModel model_;
  MechanicalState state_;
  int steps_ = 0;
  std::unique_ptr<ImplicitEuler> dynamics_;
  std::unique_ptr<StaticSolver> equilibrium_;
};

}  // namespace bcassim::python
