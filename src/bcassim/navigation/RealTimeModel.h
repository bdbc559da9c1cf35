// The model of the asynchronous mode's real-time side (thesis §4.6): it adopts each analysis the
// filter publishes (parameters and the mean's state at the analysed step), steps forward to the
// frame being shown, and gives the hidden points and the mesh there. One forward model, no
// sigma points: a frame costs one model step when the filter keeps up.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/coupling/ParameterForwardRun.h"
#include "bcassim/scene/Scene.h"

namespace bcassim {

class RealTimeModel {
 public:
  // The scene's model with its prior parameter means, at rest (step 0).
  explicit RealTimeModel(const Scene& scene);

  // From now on: `values` (physical) and, at step `step`, positions x and velocities v (3 #nodes
  // each, m and m/s; v empty for a static scene).
  void adopt(const Eigen::VectorXd& values, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
             int step);
  // New parameter values from the next step on, the state kept.
  void adoptParameters(const Eigen::VectorXd& values);
  // Steps forward to `step` (nothing when already there or past). Throws NumericalError.
  void advanceTo(int step);

  int step() const { return run_.steps(); }
  const Eigen::VectorXd& positions() const { return run_.state().x; }
  Eigen::MatrixX3d hiddenPositions() const;

 private:
  const Scene& scene_;
  ParameterForwardRun run_;
};

}  // namespace bcassim
