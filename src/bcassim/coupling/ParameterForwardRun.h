// A forward run of a scene with chosen values of its estimated parameters, one step at a time:
// the "initial" curve of an assimilation and the run `validate` compares with the truth.
#pragma once
#include <memory>
#include <vector>

#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/scene/Scene.h"

namespace bcassim {

class ParameterForwardRun {
 public:
  // The scene's model with values(i) written into parameters[i].target, from the rest state.
  ParameterForwardRun(const Scene& scene, const std::vector<EstimatedParameter>& parameters,
                      const Eigen::VectorXd& values);

  // One implicit-Euler step, or with a static scene the equilibrium of the next step's time;
  // throws NumericalError if it diverges.
  void step();
  // New values of the parameters from the next step on (the live real-time model adopts each
  // analysis this way); the state is kept.
  void setValues(const std::vector<EstimatedParameter>& parameters, const Eigen::VectorXd& values);
  // From now on each implicit-Euler step uses this frozen tangent (ImplicitEuler::stepWithTangent:
  // a force assembly and one solve) instead of assembling and solving with the state's own; null:
  // the state's own again. It must have been built for this run's dt (FrozenTangent::build);
  // static scenes ignore it. singlePrecision: its solves through the factor rounded to float
  // (ImplicitEuler::stepWithTangent).
  void useTangent(std::shared_ptr<const FrozenTangent> tangent, bool singlePrecision = false) {
    tangent_ = std::move(tangent);
    singlePrecision_ = singlePrecision;
  }
  const MechanicalModel& model() const { return model_; }
  double dt() const { return dt_; }
  bool isStatic() const { return statics_ != nullptr; }
  // Positions of mapped points in the current state, m.
  Eigen::MatrixX3d positionsOf(const std::vector<MappedPoint>& points) const;
  double time() const { return state_.t; }
  // For checkpoints: the state after steps() steps, and continuing from one.
  const MechanicalState& state() const { return state_; }
  int steps() const { return steps_; }
  void restore(const MechanicalState& state, int steps);

 private:
  MechanicalModel model_;
  MechanicalState state_;
  std::unique_ptr<ImplicitEuler> integrator_;
  std::unique_ptr<StaticSolver> statics_;         // static scenes
  std::shared_ptr<const FrozenTangent> tangent_;  // useTangent
  bool singlePrecision_ = false;
  double dt_;
  int steps_ = 0;
};

}  // namespace bcassim
