// The model of the asynchronous mode's real-time side (thesis §4.6): it adopts each analysis the
// filter publishes (parameters and the mean's state at the analysed step), steps forward to the
// frame being shown, and gives the hidden points and the mesh there. One forward model, no
// sigma points: a frame costs one model step when the filter keeps up.
#pragma once
#include <Eigen/Core>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "bcassim/BackgroundThread.h"
#include "bcassim/coupling/ParameterForwardRun.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/scene/Scene.h"

namespace bcassim {

// How the real-time model steps (implicit-Euler scenes; static ones always solve).
enum class RealTimeTangent {
  Own,  // eq. 2.16 with the state's own stiffness, assembled and solved every frame
  // eq. 2.16 with a stiffness built a few frames before (ImplicitEuler::stepWithTangent: a force
  // assembly and one solve per frame), on a thread of its own every few frames, at the state and
  // parameters of the frame it starts from; its solves go through the factor rounded to float. A
  // frame whose tangent is older than the model's largest age (twice that while a newer one is
  // being built), or that has none yet, steps with its own: on a nearly incompressible liver a
  // tangent 50 frames old made the step diverge (docs/live.md).
  Frozen,
};

class RealTimeModel {
 public:
  // The scene's model with its prior parameter means, at rest (step 0). With Frozen, the first
  // tangent (at rest, prior) starts building at once; a tangent serves frames up to
  // maxTangentAge steps from the one it was built at (2 maxTangentAge while a newer one builds).
  // A build is started when the tangent in use will be refreshEvery steps old at the next frame.
  // The defaults keep a build running a third of the time on the 2,150-node liver (one build,
  // ~45 ms, every 3 frames of 33 ms) and the hidden points within ~1 % of the liver's motion of
  // the own step's (tests/navigation).
  explicit RealTimeModel(const Scene& scene, RealTimeTangent tangent = RealTimeTangent::Own,
                         int maxTangentAge = 6, int refreshEvery = 3);
  // Waits for a tangent still being built.
  ~RealTimeModel();
  RealTimeModel(const RealTimeModel&) = delete;
  RealTimeModel& operator=(const RealTimeModel&) = delete;

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
  // Frozen: tangents built and taken into use so far (a build that failed keeps the last one),
  // and frames stepped with one.
  int tangentsAdopted() const { return tangentsAdopted_; }
  int framesWithTangent() const { return framesWithTangent_; }
  // Waits for a build in progress and takes it into use (tests and benchmarks; the real-time loop
  // never waits).
  void finishTangent();
  // Before the first frame: finishes the first tangent and takes one step with the state's own
  // stiffness, then goes back to where it was, so the first frames do not pay the own step's
  // first analysis and factorisation (132 ms on the phantom's first own step in `serve --async`).
  // Throws NumericalError.
  void warmUp();

 private:
  // Starts building the tangent of the current model and state, unless a build is running.
  void requestTangent();
  // Takes a finished build into use.
  void takeReadyTangent();

  const Scene& scene_;
  ParameterForwardRun run_;
  RealTimeTangent mode_;
  int maxTangentAge_, refreshEvery_;
  std::shared_ptr<const FrozenTangent> tangent_;
  int tangentStep_ = 0, pendingStep_ = 0;  // the steps their states were at
  int tangentsAdopted_ = 0, framesWithTangent_ = 0;
  // The copy the pending build reads; declared before builder_, whose destructor lets the build
  // underway end, so that they outlive it.
  std::optional<MechanicalModel> tangentModel_;
  MechanicalState tangentState_;
  std::future<std::shared_ptr<const FrozenTangent>> pending_;
  // Every build on one thread: its memory stays for the next (BackgroundThread.h).
  BackgroundThread builder_;
};

}  // namespace bcassim
