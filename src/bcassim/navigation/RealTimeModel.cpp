#include "bcassim/navigation/RealTimeModel.h"

#include <chrono>
#include <cstdlib>

#include "bcassim/Error.h"
#include "bcassim/live/ThreadPriority.h"

namespace bcassim {

namespace {

Eigen::VectorXd priorMeans(const Scene& scene) {
  const std::vector<EstimatedParameter>& p = scene.assimilation->parameters;
  Eigen::VectorXd v(static_cast<Eigen::Index>(p.size()));
  for (size_t i = 0; i < p.size(); ++i) v(static_cast<Eigen::Index>(i)) = p[i].mean;
  return v;
}

}  // namespace

RealTimeModel::RealTimeModel(const Scene& scene, RealTimeTangent tangent, int maxTangentAge,
                             int refreshEvery)
    : scene_(scene),
      run_(scene, scene.assimilation->parameters, priorMeans(scene)),
      mode_(tangent),
      maxTangentAge_(maxTangentAge),
      refreshEvery_(refreshEvery) {
  // The frames stepped meanwhile come first; the filter behind the camera (nice +10) after the
  // builds.
  builder_.submit([] { yieldToRealTime(5); });
  requestTangent();
}

RealTimeModel::~RealTimeModel() {
  if (pending_.valid()) pending_.wait();
}

void RealTimeModel::requestTangent() {
  if (mode_ != RealTimeTangent::Frozen || run_.isStatic() || pending_.valid()) return;
  tangentModel_.emplace(run_.model());
  tangentState_ = run_.state();
  pendingStep_ = run_.steps();
  // The last tangent's factor gives the build its ordering (FrozenTangent::build).
  std::shared_ptr<const FrozenTangent> previous = tangent_;
  const double dt = run_.dt();
  pending_ = builder_.submit([this, previous, dt] {
    std::shared_ptr<const FrozenTangent> built = FrozenTangent::build(
        *tangentModel_, tangentState_, dt, previous ? &previous->factor() : nullptr);
    // Its float copy here, not at the real-time thread's first solve with it.
    built->factor().prepareSinglePrecision();
    return built;
  });
}

void RealTimeModel::takeReadyTangent() {
  if (!pending_.valid() || pending_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
    return;
  try {
    tangent_ = pending_.get();
    tangentStep_ = pendingStep_;
    ++tangentsAdopted_;
  } catch (const NumericalError&) {
    // Not positive definite there: the last tangent stays (any tangent gives a consistent step).
  }
}

void RealTimeModel::finishTangent() {
  if (pending_.valid()) pending_.wait();
  takeReadyTangent();
}

void RealTimeModel::warmUp() {
  finishTangent();
  const MechanicalState state = run_.state();
  const int steps = run_.steps();
  run_.useTangent(nullptr);
  run_.step();
  run_.restore(state, steps);
}

void RealTimeModel::adopt(const Eigen::VectorXd& values, const Eigen::VectorXd& x,
                          const Eigen::VectorXd& v, int step) {
  run_.setValues(scene_.assimilation->parameters, values);
  MechanicalState s = run_.state();
  s.x = x;
  if (v.size() == x.size()) s.v = v;
  s.t = step * scene_.dt();
  run_.restore(s, step);
  takeReadyTangent();
  requestTangent();
}

void RealTimeModel::adoptParameters(const Eigen::VectorXd& values) {
  run_.setValues(scene_.assimilation->parameters, values);
  takeReadyTangent();
  requestTangent();
}

void RealTimeModel::advanceTo(int step) {
  if (run_.steps() >= step) return;
  while (run_.steps() < step) {
    takeReadyTangent();
    // While a newer tangent is being built, the one in use serves up to twice as long: an own step
    // costs several frozen ones and would take the build's core (on the phantom liver in
    // `serve --async`, the first builds came late and frames 7-12 all stepped with their own).
    const int age = std::abs(run_.steps() - tangentStep_);
    const int oldest = pending_.valid() ? 2 * maxTangentAge_ : maxTangentAge_;
    const bool young = tangent_ && age < oldest;
    // The factor rounded to float: half the memory traffic of a solve, and a trajectory that
    // differs from the double one by ~1e-9 of the motion (tests/navigation).
    run_.useTangent(young ? tangent_ : nullptr, true);
    run_.step();
    if (young) ++framesWithTangent_;
  }
  // The next frame starts here: a tangent for it starts building now when due.
  takeReadyTangent();
  if (!tangent_ || std::abs(run_.steps() - tangentStep_) >= refreshEvery_) requestTangent();
}

Eigen::MatrixX3d RealTimeModel::hiddenPositions() const {
  return run_.positionsOf(scene_.hidden.points);
}

}  // namespace bcassim
