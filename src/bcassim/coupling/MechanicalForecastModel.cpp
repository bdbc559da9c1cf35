#include "bcassim/coupling/MechanicalForecastModel.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"

namespace bcassim {
namespace {

// One integrator steps every sigma point of its worker in turn: extrapolating the initial guess
// across different states would not predict the next one.
ImplicitEulerOptions withoutExtrapolation(ImplicitEulerOptions options) {
  options.extrapolateGuess = false;
  return options;
}

}  // namespace

MechanicalForecastModel::MechanicalForecastModel(const MechanicalModel& model,
                                                 ImplicitEulerOptions integrator,
                                                 std::vector<MappedPoint> observed,
                                                 std::vector<ModelParameterTarget> parameters,
                                                 const MechanicalState& initial,
                                                 const ForecastModelOptions& options, int worker,
                                                 std::shared_ptr<SharedFactorization> shared)
    : model_(model),
      integrator_(model_, makeLinearSolver(options.solver, options.refresh),
                  withoutExtrapolation(integrator)),
      observed_(std::move(observed)),
      parameters_(std::move(parameters)),
      reference_(initial),
      options_(options),
      worker_(worker),
      shared_(options.shareFactorization || options.meanTangent || options.statics
                  ? std::move(shared)
                  : nullptr) {
  if (options_.statics) {
    if (options_.layout.positions || options_.layout.velocities)
      throw std::invalid_argument(
          "MechanicalForecastModel: static frames estimate parameters only");
    if (!shared_)
      throw std::invalid_argument(
          "MechanicalForecastModel: static frames need a "
          "SharedFactorization (worker 0 solves the mean)");
  }
  for (const ModelParameterTarget& target : parameters_)
    hasPose_ = hasPose_ || std::holds_alternative<ObservationPoseTarget>(target);
  if (hasPose_) poseCentre_ = model_.mesh->V.colwise().mean().transpose();
  if (options_.tangentBackgroundSteps > options_.tangentRefreshEvery)
    throw std::invalid_argument(
        "MechanicalForecastModel: a background build is adopted before the next one is due "
        "(tangentBackgroundSteps <= tangentRefreshEvery)");
  if (options_.meanTangent) {
    if (!shared_)
      throw std::invalid_argument(
          "MechanicalForecastModel: meanTangent needs a SharedFactorization");
    if (worker_ == 0) buildMeanTangent();
  }
  if (options_.statics) {
    // Newton's systems have the mean tangent's pattern: its analysis serves them (one
    // fill-reducing ordering per run instead of one more per worker). Whoever solves in full in the
    // first frame (worker 0 the analysed mean, or every worker its own sigma points without the
    // mean's tangent) factorises once now: the first frame's Newton otherwise made the
    // factorisation's plan and first touched its memory, ~85 ms of the mestdagh liver's ~500 ms
    // first frame.
    statics_ = std::make_unique<StaticSolver>(
        model_,
        makeLinearSolver(options.solver, options.refresh,
                         shared_->tangent ? &shared_->tangent->factor() : nullptr),
        *options_.statics);
    if (worker_ == 0 || !options_.meanTangent) statics_->warmUp(model_, reference_.t, reference_.x);
  }
  // Static frames too: their builds have N frames, but a cold one took twice as long (page
  // faults) and made every other adoption wait on the mestdagh liver.
  if (options_.meanTangent && worker_ == 0 && options_.tangentInBackground) warmUpBuilder();
}

// The background builds' thread, started here and made to build three tangents that are thrown
// away, all alive at the end, as the steps can hold the tangent in use, the one it replaced and
// the next while it is built. Their memory stays with the thread (BackgroundThread.h; the CLI
// keeps freed blocks, cli/main.cpp), and the run's builds find it: before, the first ones took
// 7,000, 3,600 and 1,700 page faults and 110, 67 and 47 ms of CPU on LiTS-3 against 18 faults and
// ~29 ms later, and the steps that adopted them waited (two warm-up builds left 1,500 faults at
// the third; docs/benchmarks.md §7). Nothing computed here is kept.
void MechanicalForecastModel::warmUpBuilder() {
  builder_ = std::make_unique<BackgroundThread>();
  if (!shared_->tangent) return;
  const CholeskyFactor* analysis = &shared_->tangent->factor();
  auto build = [&] { return makeTangent(model_, reference_, analysis); };
  try {
    std::shared_ptr<const FrozenTangent> first = builder_->submit(build).get();
    std::shared_ptr<const FrozenTangent> second = builder_->submit(build).get();
    builder_->submit(build).get();
  } catch (const NumericalError&) {
    // The model's own tangent was just built from the same state: the steps will meet this too.
  }
}

ForecastStats& ForecastStats::operator+=(const ForecastStats& o) {
  assemblySeconds += o.assemblySeconds;
  solveSeconds += o.solveSeconds;
  tangentSeconds += o.tangentSeconds;
  tangentWaitSeconds += o.tangentWaitSeconds;
  forecasts += o.forecasts;
  tangentFailures += o.tangentFailures;
  stepRetries += o.stepRetries;
  linearIterations += o.linearIterations;
  factorizations += o.factorizations;
  return *this;
}

ForecastStats MechanicalForecastModel::takeStats() {
  ForecastStats out = stats_;
  stats_ = {};
  return out;
}

// The mean's tangent: the implicit-Euler W of a step of dt, or the stiffness K of a static frame;
// its factor's float copy too where the steps solve with it (static frames' chords always,
// dynamic steps with tangentSinglePrecision), made here, on the building thread, not by the
// frame that first solves with it.
std::shared_ptr<const FrozenTangent> MechanicalForecastModel::makeTangent(
    const MechanicalModel& model, const MechanicalState& state, const CholeskyFactor* analysis,
    int threads) const {
  std::shared_ptr<const FrozenTangent> built =
      options_.statics
          ? FrozenTangent::buildStatic(model, state, analysis, threads)
          : FrozenTangent::build(model, state, integrator_.options().dt, analysis, threads);
  if (options_.statics || options_.tangentSinglePrecision) built->factor().prepareSinglePrecision();
  return built;
}

void MechanicalForecastModel::buildMeanTangent(int threads) {
  const CholeskyFactor* analysis = shared_->tangent ? &shared_->tangent->factor() : nullptr;
  shared_->stepsSinceTangent = 0;
  try {
    adoptTangent(makeTangent(model_, reference_, analysis, threads));
  } catch (const NumericalError&) {
    // Static frames do without (every forecast then solves its own equilibrium).
    if (!shared_->tangent && !options_.statics) throw;  // nothing to fall back on
    ++stats_.tangentFailures;
  }
}

// The mean's tangent from the Newton solve that just made reference_ its equilibrium: its last
// factorisation, one Newton step before it, instead of one more there (StaticSolver::
// newtonTangent; ~45 ms of the mestdagh liver's first frame). False where that solve left none.
bool MechanicalForecastModel::adoptNewtonTangent() {
  std::shared_ptr<const FrozenTangent> tangent = statics_->newtonTangent(model_, reference_);
  if (!tangent) return false;
  tangent->factor().prepareSinglePrecision();
  shared_->stepsSinceTangent = 0;
  adoptTangent(std::move(tangent), false);
  return true;
}

void MechanicalForecastModel::adoptTangent(std::shared_ptr<const FrozenTangent> tangent,
                                           bool factorized) {
  shared_->tangent = std::move(tangent);
  stats_.tangentSeconds += shared_->tangent->buildSeconds();
  if (factorized) ++stats_.factorizations;
}

Eigen::Index MechanicalForecastModel::observableSize() const {
  return 3 * (options_.observeNodes ? model_.mesh->numNodes()
                                    : static_cast<Eigen::Index>(observed_.size()));
}

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
  for (size_t i = 0; i < parameters_.size(); ++i) {
    const auto index = static_cast<Eigen::Index>(i);
    if (const auto* pose = std::get_if<ObservationPoseTarget>(&parameters_[i]))
      pose_(pose->component) = params(index);
    else
      applyParameter(parameters_[i], params(index), model_);
  }
}

void MechanicalForecastModel::observe(const MechanicalState& s, Eigen::VectorXd& observable) const {
  if (options_.observeNodes) {
    observable = s.x;
  } else {
    observable.resize(observableSize());
    for (size_t i = 0; i < observed_.size(); ++i)
      observable.segment<3>(3 * i) = interpolate(observed_[i], *model_.mesh, s.x);
  }
  if (!hasPose_) return;
  // Where the observations see these points: the model's frame moved by the pose.
  const Vec3 w = pose_.head<3>();
  const double angle = w.norm();
  const Eigen::Matrix3d R = angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
                                      : Eigen::Matrix3d::Identity();
  const Vec3 shift = poseCentre_ + pose_.tail<3>() - R * poseCentre_;
  for (Eigen::Index i = 0; i < observable.size(); i += 3)
    observable.segment<3>(i) = R * observable.segment<3>(i) + shift;
}

// The equilibrium at time t from s (the reference: its positions warm-start Newton, the loads
// ramp from those it balances), with the model's parameters as they are now. Worker 0 publishes
// its factorisation, the others precondition with the one published (thesis Alg. 4/5).
void MechanicalForecastModel::solveStatic(MechanicalState& s, double t) {
  auto* reuse = dynamic_cast<FactorizedPcgSolver*>(&statics_->linearSolver());
  if (reuse && worker_ != 0 && shared_->factor) reuse->shareFactor(shared_->factor);
  const int factorizationsBefore = reuse ? reuse->factorizations() : 0;
  statics_->continueFromLoad(referenceLoad_);
  const auto start = Clock::now();
  const StaticReport report = statics_->solve(model_, t, s.x);
  stats_.solveSeconds += secondsSince(start);
  stats_.linearIterations += report.iterations;
  stats_.stepRetries += report.retries;
  if (reuse) {
    stats_.factorizations += reuse->factorizations() - factorizationsBefore;
    if (worker_ == 0) {
      shared_->next = reuse->factor();
      if (shared_->withinStep) shared_->factor = shared_->next;
    }
  }
  s.v.setZero();
  s.t = t;
}

// The analysed mean's equilibrium by Newton where the chord did not reach it: from the chord's
// last iterate (its steps lowered the residual or the energy, so it is mostly nearer than the
// last frame's equilibrium: fewer Newton iterations, each a factorisation; not always, see
// docs/benchmarks.md §6), else, or where Newton fails from there, from the last frame's
// equilibrium.
void MechanicalForecastModel::solveStaticFrom(Eigen::VectorXd& chordEnd, double t) {
  if (chordEnd.size() > 0) {
    MechanicalState from = reference_;
    from.x = std::move(chordEnd);
    try {
      solveStatic(from, t);
      reference_ = std::move(from);
      return;
    } catch (const StepFailure&) {
      ++stats_.stepRetries;
    }
  }
  solveStatic(reference_, t);
}

// With the mean's tangent, a sigma point's frame is one chord step from the analysed mean's
// equilibrium: the equilibrium linearised about the mean, as the filter's sigma points only
// probe the parameters' spread about it. A step that inverts an element solves in full.
void MechanicalForecastModel::staticForecast(const Eigen::VectorXd& params,
                                             Eigen::VectorXd& newState,
                                             Eigen::VectorXd& observable) {
  work_ = reference_;
  setParameters(params);
  ++stats_.forecasts;
  const double t = frameTime();
  bool solved = false;
  if (options_.meanTangent && shared_->tangent) {
    const auto start = Clock::now();
    try {
      statics_->chordSolve(model_, t, work_.x, *shared_->tangent, 1, true);
      work_.v.setZero();
      work_.t = t;
      solved = true;
    } catch (const NumericalError&) {
      work_ = reference_;
      ++stats_.stepRetries;
    }
    stats_.solveSeconds += secondsSince(start);
  }
  if (!solved) solveStatic(work_, t);
  newState.resize(0);
  observe(work_, observable);
}

// The analysed mean's equilibrium becomes the reference: solved by worker 0, copied by the
// others (endStep runs in worker order), so that it costs one solve whatever the thread count.
void MechanicalForecastModel::staticEndStep(const Eigen::VectorXd& params) {
  settleStaticMean(params, false);
  recentred_ = false;
}

bool MechanicalForecastModel::recentre(const Eigen::VectorXd& /*state*/,
                                       const Eigen::VectorXd& params) {
  if (!statics_) return false;
  setParameters(params);
  settleStaticMean(params, true);
  recentred_ = true;
  return shared_->recentreWorthwhile;
}

// The mean's equilibrium at this frame's time with `params` (set already) as the reference.
// Re-centring within a frame needs a tangent at it (the forecasts about it linearise with it): one
// is built there unless the tangent in use solved it in one or two chord steps; the schedule of
// refreshes counts frames, not re-centrings.
void MechanicalForecastModel::settleStaticMean(const Eigen::VectorXd& params, bool recentring) {
  meanParams_ = params;
  if (worker_ == 0) {
    shared_->factor = shared_->next;
    const double t = frameTime();
    // A re-centred mean is a linearisation point: its sigma points' chord steps remove what is
    // left of its residual to first order, so 1 % of the forces (~1 % of the motion) is close
    // enough (the mestdagh liver's first frames: 2 of 9 Newton iterations fewer, the estimates
    // the same to the printed digit). The frame's own equilibrium is solved to the scene's
    // tolerance at its end (staticEndStep), from it.
    const double tolerance = statics_->relativeTolerance();
    struct Restore {
      StaticSolver& statics;
      double tolerance;
      ~Restore() { statics.setRelativeTolerance(tolerance); }
    } restore{*statics_, tolerance};
    constexpr double kRecentringTolerance = 1e-2;
    if (recentring) statics_->setRelativeTolerance(std::max(tolerance, kRecentringTolerance));
    // A build due at the end of this frame serves its mean already: the mean's chord, which
    // stalls as its tangent ages, is the frame's cost (the sigma points took the older one).
    if (options_.meanTangent && !recentring) adoptBuildIfDue(shared_->stepsSinceTangent + 1);
    Eigen::VectorXd chordEnd;
    const bool chorded = chordMean(t, chordEnd);
    if (!chorded) {
      // Newton's factorisations while the other workers wait: on their threads too.
      statics_->linearSolver().setFactorThreads(inFrameThreads());
      try {
        solveStaticFrom(chordEnd, t);
      } catch (...) {
        statics_->linearSolver().setFactorThreads(1);
        throw;
      }
      statics_->linearSolver().setFactorThreads(1);
    }
    model_.externalForces(reference_.t, referenceLoad_);
    shared_->staticMean = reference_;
    shared_->staticMeanLoad = referenceLoad_;
    if (shared_->next) shared_->factor = shared_->next;
    // Without the mean's tangent every forecast solves its own equilibrium: forecasts about this
    // mean sample the response there, where the ones about the forecast mean did not.
    shared_->recentreWorthwhile = !options_.meanTangent || !chorded || meanChordSteps_ > 2;
    if (!options_.meanTangent) return;
    if (chorded && !recentring) {
      refreshMeanTangent();
    } else if (shared_->recentreWorthwhile) {
      // The tangent did not serve (or, re-centring, was not this equilibrium's): a new one at
      // this equilibrium now, whatever the schedule. (A background build would serve N frames
      // later, and the frames between fell back to Newton too: 250-400 ms each at the mestdagh
      // liver's start.)
      // After Newton, its last factorisation is the tangent: one fewer in the frame.
      discardPendingTangent();
      if (chorded || !adoptNewtonTangent()) buildMeanTangent(inFrameThreads());
    }
  } else {
    reference_ = shared_->staticMean;
    referenceLoad_ = shared_->staticMeanLoad;
  }
}

// The analysed mean's equilibrium by chord iterations with the mean's tangent, from the previous
// one. Where they get closer but not close enough, they go on with the same tangent if their
// contraction so far says that a second round reaches the tolerance (a few more steps cost less
// than a factorisation); otherwise, or if that round does not converge either, the tangent is
// rebuilt at their last iterate (it had grown too far from this frame's: it is then the new mean
// tangent) and they go on once. That includes a round whose residual did not fall, its steps
// having lowered only the energy (a nearly incompressible organ after a large load change, the
// first frame's): one factorisation there and a chord cost less than the 2-7 Newton iterations
// that otherwise follow (the mestdagh liver's first frames, docs/benchmarks.md §6). False
// (reference_ untouched) where that does not converge either, or a step inverts an element:
// Newton solves it then, from `end` (set to their last iterate when they took steps and none
// failed, else left empty).
bool MechanicalForecastModel::chordMean(double t, Eigen::VectorXd& end) {
  if (!options_.meanTangent || !shared_->tangent) return false;
  constexpr int kChordIterations = 10;
  const auto start = Clock::now();
  Eigen::VectorXd x = reference_.x;
  bool converged = false;
  bool continued = false;
  bool rebuilt = false;
  bool failed = false;  // a step inverted an element or a tangent could not be factorised
  meanChordSteps_ = 0;
  try {
    for (;;) {
      // Going on with the same tangent is one chord (its Anderson history kept); a rebuilt
      // tangent starts another.
      const StaticReport report =
          continued && !rebuilt
              ? statics_->continueChord(model_, t, x, *shared_->tangent, kChordIterations, true,
                                        options_.meanThreads)
              : statics_->chordSolve(model_, t, x, *shared_->tangent, kChordIterations, true,
                                     options_.meanThreads);
      stats_.linearIterations += report.iterations;
      meanChordSteps_ += report.iterations;
      converged = report.converged;
      if (converged || rebuilt) break;
      const bool lowered = report.residualNorm < report.initialResidualNorm;
      if (!continued && lowered && chordStepsToGo(report) <= kChordIterations) {
        continued = true;
        continue;
      }
      MechanicalState at = reference_;
      at.x = x;
      at.t = t;
      rebuildMeanTangentAt(at);
      rebuilt = true;
    }
  } catch (const NumericalError&) {
    converged = false;
    failed = true;
  }
  stats_.solveSeconds += secondsSince(start);
  if (!converged) {
    ++stats_.stepRetries;
    if (meanChordSteps_ > 0 && !failed) end = std::move(x);
    return false;
  }
  reference_.x = std::move(x);
  reference_.v.setZero();
  reference_.t = t;
  return true;
}

// A static mean tangent at `at` now (replacing any background build underway), the model's
// parameters as they are. Throws NumericalError if it cannot be factorised.
void MechanicalForecastModel::rebuildMeanTangentAt(const MechanicalState& at) {
  discardPendingTangent();
  shared_->stepsSinceTangent = 0;
  adoptTangent(makeTangent(model_, at, &shared_->tangent->factor(), inFrameThreads()));
}

void MechanicalForecastModel::forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                                       Eigen::VectorXd& newState, Eigen::VectorXd& observable) {
  if (statics_) {
    staticForecast(params, newState, observable);
    return;
  }
  work_ = reference_;
  unpackState(state, work_);
  setParameters(params);
  ++stats_.forecasts;
  if (options_.meanTangent) {
    integrator_.stepWithTangent(model_, work_, *shared_->tangent, options_.tangentSinglePrecision);
    const StepTimings& t = integrator_.lastTimings();
    stats_.assemblySeconds += t.assembly;
    stats_.solveSeconds += t.solve;
    stats_.stepRetries += t.retries;
    newState = packState(work_);
    observe(work_, observable);
    return;
  }
  // Thesis Alg. 4/5: worker 0 refreshes the factorisation when its policy says so; the others
  // precondition their PCG with the one it published (SharedFactorization).
  auto* reuse = dynamic_cast<FactorizedPcgSolver*>(&integrator_.linearSolver());
  if (shared_ && reuse && worker_ != 0 && shared_->factor) reuse->shareFactor(shared_->factor);
  const int factorizationsBefore = reuse ? reuse->factorizations() : 0;
  integrator_.step(model_, work_);
  {
    const StepTimings& t = integrator_.lastTimings();
    stats_.assemblySeconds += t.assembly;
    stats_.solveSeconds += t.solve;
    stats_.linearIterations += t.lastSolve.iterations;
    stats_.stepRetries += t.retries;
    if (reuse) stats_.factorizations += reuse->factorizations() - factorizationsBefore;
  }
  if (shared_ && reuse && worker_ == 0) {
    shared_->next = reuse->factor();
    if (shared_->withinStep) shared_->factor = shared_->next;
  }
  newState = packState(work_);
  observe(work_, observable);
}

void MechanicalForecastModel::endStep(const Eigen::VectorXd& state, const Eigen::VectorXd& params) {
  if (statics_) {
    setParameters(params);
    staticEndStep(params);
    return;
  }
  if (shared_ && worker_ == 0) shared_->factor = shared_->next;
  setParameters(params);
  meanParams_ = params;
  if (options_.layout.positions && options_.layout.velocities) {
    unpackState(state, reference_);
    reference_.t += integrator_.options().dt;
    refreshMeanTangent();
    return;
  }
  // Without the full mechanical state in the filter, the mean trajectory is continued by one more
  // step with the analysed parameters, then corrected by whatever part the filter does carry.
  // Worker 0 comes first (endStep runs in worker order) and may rebuild the tangent below: the
  // others step with the one it stepped with.
  if (options_.meanTangent && worker_ == 0) shared_->endStepTangent = shared_->tangent;
  if (options_.meanTangent)
    integrator_.stepWithTangent(model_, reference_, *shared_->endStepTangent,
                                options_.tangentSinglePrecision);
  else
    integrator_.step(model_, reference_);
  stats_.stepRetries += integrator_.lastTimings().retries;
  unpackState(state, reference_);
  refreshMeanTangent();
}

void MechanicalForecastModel::refreshMeanTangent() {
  if (!options_.meanTangent || worker_ != 0) return;
  const bool due = ++shared_->stepsSinceTangent >= options_.tangentRefreshEvery;
  // A background build replaces the tangent B steps after it was launched (B =
  // tangentBackgroundSteps), whatever the thread timing (waiting for it if need be): the
  // schedule, and the result, are the same on any machine. The tangent in use is thus B to
  // B + N - 1 steps old (N = tangentRefreshEvery): older elastic tangents can make the step
  // unstable (docs/liver.md), so dynamic steps adopt after one step unless told otherwise.
  // Static frames have no such instability (the mean is solved to equilibrium): their build is
  // adopted when the next one is due, so that it has N frames to finish on the other core, and
  // at the start of that frame's mean solve (staticEndStep), which it serves already.
  adoptBuildIfDue(shared_->stepsSinceTangent);
  // A static tangent that still solved the mean in one chord step (two: the second mends a
  // single-precision solve's rounding) is exact there, as a linear law's always is: a new one
  // would cost a factorisation and change nothing. An aged Neo-Hookean one takes 4-10.
  if (!due || (statics_ && meanChordSteps_ <= 2)) return;
  if (!options_.tangentInBackground) {
    buildMeanTangent();
    return;
  }
  shared_->stepsSinceTangent = 0;
  // The build's own copy of the model (read by its thread): copied once, then only the
  // estimated parameters change.
  if (!tangentModel_) tangentModel_ = model_;
  for (size_t i = 0; i < parameters_.size(); ++i)
    applyParameter(parameters_[i], meanParams_(static_cast<Eigen::Index>(i)), *tangentModel_);
  tangentState_ = reference_;
  if (!builder_) builder_ = std::make_unique<BackgroundThread>();
  pendingTangent_ = builder_->submit([this, analysis = shared_->tangent] {
    return makeTangent(*tangentModel_, tangentState_, analysis ? &analysis->factor() : nullptr);
  });
}

// The background build, once it has had its steps (`stepsSince` counts the step that is ending).
void MechanicalForecastModel::adoptBuildIfDue(int stepsSince) {
  const int adoptAfter = options_.tangentBackgroundSteps > 0 ? options_.tangentBackgroundSteps
                         : statics_                          ? options_.tangentRefreshEvery
                                                             : 1;
  if (!pendingTangent_.valid() || stepsSince < adoptAfter) return;
  const auto waitStart = Clock::now();
  pendingTangent_.wait();
  stats_.tangentWaitSeconds += secondsSince(waitStart);
  try {
    adoptTangent(pendingTangent_.get());
  } catch (const NumericalError&) {
    ++stats_.tangentFailures;
  }
}

// A build underway is finished (its thread reads this model's members) and thrown away.
void MechanicalForecastModel::discardPendingTangent() {
  if (pendingTangent_.valid()) pendingTangent_.wait();
  pendingTangent_ = {};
}

void MechanicalForecastModel::restoreReference(const MechanicalState& reference,
                                               const Eigen::VectorXd& params) {
  discardPendingTangent();
  reference_ = reference;
  setParameters(params);
  meanParams_ = params;
  // A static reference is an equilibrium under the loads of its time with these parameters.
  if (statics_) model_.externalForces(reference_.t, referenceLoad_);
  if (options_.meanTangent && worker_ == 0) buildMeanTangent();
}

Eigen::MatrixX3d MechanicalForecastModel::positionsOf(
    const std::vector<MappedPoint>& points) const {
  Eigen::MatrixX3d out(points.size(), 3);
  for (size_t i = 0; i < points.size(); ++i)
    out.row(i) = interpolate(points[i], *model_.mesh, reference_.x).transpose();
  return out;
}

}  // namespace bcassim
