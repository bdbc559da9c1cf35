// The one place where the FEM meets the filter: implements ForecastModel (simulate one step from a
// given state and parameters, or solve one quasi-static frame; expose marker or node positions)
// over a MechanicalModel and implicit Euler or the static solver.
#pragma once
#include <algorithm>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "bcassim/BackgroundThread.h"
#include "bcassim/assimilation/ForecastModel.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/mechanics/ImplicitEuler.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/CholeskyFactor.h"
#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"
#include "bcassim/mesh/BarycentricMap.h"
#include "bcassim/scene/ModelParameter.h"

namespace bcassim {

struct ForecastStateLayout {
  bool positions = true;   // carry node positions (3N) in the stochastic state
  bool velocities = true;  // carry node velocities (3N) after the positions
};

// Where worker 0's factorisation is published for the other workers (thesis Alg. 4/5). Worker 0
// leaves its factor in `next` after each forecast; at endStep it becomes `factor`, which the other
// workers precondition with during the following step. All sigma points of a step can thus run
// at once and still reuse one factorisation, deterministically. With `withinStep` (needs
// FilterOptions::firstSigmaPointAlone) the others use worker 0's factor of the same step.
struct SharedFactorization {
  std::shared_ptr<CholeskyFactor> factor;
  std::shared_ptr<CholeskyFactor> next;
  bool withinStep = false;
  // With ForecastModelOptions::meanTangent: the tangent every worker steps with, rebuilt by worker
  // 0 at the analysed mean in endStep().
  std::shared_ptr<const FrozenTangent> tangent;
  // The tangent every worker continues its reference with in endStep() (without the full state):
  // the one of the step that ends, kept by worker 0 before it replaces `tangent`, so that every
  // worker's reference is the same whatever worker 0 rebuilds first.
  std::shared_ptr<const FrozenTangent> endStepTangent;
  int stepsSinceTangent = 0;
  // Static frames: worker 0's equilibrium at the analysed mean (endStep), which the other workers
  // copy at theirs (endStep runs in worker order), and the external forces it balances.
  MechanicalState staticMean;
  Eigen::VectorXd staticMeanLoad;
  // Worker 0's answer to the last recentre(), which the others give too.
  bool recentreWorthwhile = false;
};

// What one worker's forecasts cost since the last takeStats(): CPU seconds in each part.
struct ForecastStats {
  double assemblySeconds = 0, solveSeconds = 0, tangentSeconds = 0;
  // Wall time worker 0 waited at endStep() for a background tangent to finish.
  double tangentWaitSeconds = 0;
  int forecasts = 0, linearIterations = 0, factorizations = 0;
  // Mean tangents that were not positive definite (the previous one was kept: any tangent gives
  // a consistent step, see ImplicitEuler::stepWithTangent).
  int tangentFailures = 0;
  // Failed steps redone as two half steps (ImplicitEuler::step), over the forecasts and the mean.
  int stepRetries = 0;
  ForecastStats& operator+=(const ForecastStats& o);
};

struct ForecastModelOptions {
  ForecastStateLayout layout;
  std::string solver = "factorized-pcg";  // any makeLinearSolver name
  RefreshPolicy refresh;                  // factorized-pcg policy
  // Share worker 0's factorisation with the other workers (see SharedFactorization).
  bool shareFactorization = true;
  // Step every forecast with the tangent of the analysed mean (ImplicitEuler::stepWithTangent),
  // rebuilt every tangentRefreshEvery steps; needs a shared SharedFactorization.
  bool meanTangent = false;
  int tangentRefreshEvery = 1;
  // Build the mean's tangent on a thread of its own while the next step runs; it replaces the
  // tangent in use at the end of that step (or of a later one, tangentBackgroundSteps), so the
  // forecasts step with a tangent 1 to N steps old (N = tangentRefreshEvery), deterministically.
  bool tangentInBackground = false;
  // Steps a background build is given before it replaces the tangent in use (1 to
  // tangentRefreshEvery): it runs beside the forecasts of these steps and the idle time between
  // frames, and the tangent is that many steps older. 0: 1 for dynamic steps (older elastic
  // tangents can make a step unstable), tangentRefreshEvery for static frames.
  int tangentBackgroundSteps = 0;
  // Solve with the mean tangent's factor rounded to float (CholeskyFactor::solveSinglePrecision):
  // ~40 % less solve time on the liver, and a step ~1e-7 of its increment from the double one.
  // The rounded copy is made where the tangent is built (the background thread if any).
  // Dynamic steps only: static frames choose their own precision.
  bool tangentSinglePrecision = false;
  // Quasi-static frames: every forecast is the equilibrium (StaticSolver, Newton) under the
  // loads of the next frame's time with the sigma point's parameters, warm-started from the
  // analysed mean's equilibrium of the frame before; the filter then estimates parameters only
  // (layout all false). The solver's factorisation is shared as for implicit Euler. With
  // meanTangent, a forecast is instead one chord step with the stiffness of the analysed mean's
  // equilibrium (the equilibrium linearised about the mean), and the mean's own equilibrium is
  // reached by chord iterations with it (Newton where they do not converge); the tangent is
  // rebuilt there every tangentRefreshEvery frames.
  std::optional<StaticOptions> statics;
  // Static frames with meanTangent: the analysed mean's chord iterations split their force
  // assemblies and solves over this many threads (the workers are idle then), with the same
  // result for any count >= 1; 0 keeps them on worker 0's thread with the serial kernels.
  int meanThreads = 0;
  // The observable is every node's position (3 x nodes, for an observation operator that needs
  // the surface: a point cloud) instead of the markers' positions.
  bool observeNodes = false;
};

class MechanicalForecastModel final : public ForecastModel {
 public:
  // `model` is copied (each worker owns its mechanics); `observed` are the marker points;
  // `parameters` say what each estimated scalar sets; `initial` is the reference state at t0.
  MechanicalForecastModel(const MechanicalModel& model, ImplicitEulerOptions integrator,
                          std::vector<MappedPoint> observed,
                          std::vector<ModelParameterTarget> parameters,
                          const MechanicalState& initial, const ForecastModelOptions& options,
                          int worker, std::shared_ptr<SharedFactorization> shared);

  Eigen::Index stateSize() const override;
  Eigen::Index observableSize() const override;
  void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                Eigen::VectorXd& newState, Eigen::VectorXd& predicted) override;
  void endStep(const Eigen::VectorXd& state, const Eigen::VectorXd& params) override;
  // Static frames only: the equilibrium at these parameters, at this frame's time, becomes the
  // reference the frame's next forecasts linearise about, with a tangent built there (with
  // `tangent: mean`). False for dynamic steps (nothing changed), and where the tangent the
  // forecasts used solved this equilibrium in one or two chord steps (a linear law's always
  // does): forecasts about it would be the same affine map, so a re-forecast could not change the
  // analysis (the reference has moved; endStep() ends the frame from it).
  bool recentre(const Eigen::VectorXd& state, const Eigen::VectorXd& params) override;

  // The stochastic physical part of a mechanical state, per the layout (for the initial mean).
  Eigen::VectorXd packState(const MechanicalState& s) const;
  // Reference (analysed) mechanical state: the mean the next step starts from.
  const MechanicalState& reference() const { return reference_; }
  const MechanicalModel& model() const { return model_; }
  // Predicted positions of any mapped points in the reference state (validation points, tumours).
  Eigen::MatrixX3d positionsOf(const std::vector<MappedPoint>& points) const;
  // Timings of this worker's last implicit-Euler forecast (assembly / solve), for benchmarks.
  const StepTimings& lastTimings() const { return integrator_.lastTimings(); }
  // Resuming from a checkpoint: the reference state and the analysed (physical) parameters the
  // checkpointed step ended with. Worker 0 rebuilds the mean tangent there, synchronously (an
  // uninterrupted run would step with one built a step or two earlier, in the background).
  void restoreReference(const MechanicalState& reference, const Eigen::VectorXd& params);
  // Costs accumulated since the last call, which resets them.
  ForecastStats takeStats();

 private:
  void unpackState(const Eigen::VectorXd& state, MechanicalState& s) const;
  void setParameters(const Eigen::VectorXd& params);
  void observe(const MechanicalState& s, Eigen::VectorXd& observable) const;
  void solveStatic(MechanicalState& s, double t);
  void staticForecast(const Eigen::VectorXd& params, Eigen::VectorXd& newState,
                      Eigen::VectorXd& observable);
  void staticEndStep(const Eigen::VectorXd& params);
  void settleStaticMean(const Eigen::VectorXd& params, bool recentring);
  // The time the frame's forecasts solve for: the next one, or the reference's own once the
  // frame was re-centred.
  double frameTime() const {
    return recentred_ ? reference_.t : reference_.t + integrator_.options().dt;
  }
  bool chordMean(double t, Eigen::VectorXd& end);
  void solveStaticFrom(Eigen::VectorXd& chordEnd, double t);
  void rebuildMeanTangentAt(const MechanicalState& at);
  // `threads`: its factorisation's (1 on the background builder, which runs beside the workers).
  std::shared_ptr<const FrozenTangent> makeTangent(const MechanicalModel& model,
                                                   const MechanicalState& state,
                                                   const CholeskyFactor* analysis,
                                                   int threads = 1) const;
  void buildMeanTangent(int threads = 1);
  bool adoptNewtonTangent();
  // Threads for the work of the analysed mean while the other workers wait (static frames).
  int inFrameThreads() const { return std::max(1, options_.meanThreads); }
  // `factorized`: the tangent made a factorisation of its own (counted in the stats).
  void adoptTangent(std::shared_ptr<const FrozenTangent> tangent, bool factorized = true);
  void refreshMeanTangent();
  void adoptBuildIfDue(int stepsSince);
  void discardPendingTangent();
  void warmUpBuilder();

  MechanicalModel model_;
  ImplicitEuler integrator_;
  std::unique_ptr<StaticSolver> statics_;  // with ForecastModelOptions::statics
  Eigen::VectorXd referenceLoad_;          // f_ext the reference balances (static; empty: none)
  std::vector<MappedPoint> observed_;
  std::vector<ModelParameterTarget> parameters_;
  // The observations' pose (ObservationPoseTarget): a rotation vector (rad) about the rest
  // centroid and a translation (m) applied to the observable; zero: the model's own frame.
  bool hasPose_ = false;
  Eigen::Matrix<double, 6, 1> pose_ = Eigen::Matrix<double, 6, 1>::Zero();
  Vec3 poseCentre_ = Vec3::Zero();
  MechanicalState reference_, work_;
  ForecastModelOptions options_;
  int worker_;
  std::shared_ptr<SharedFactorization> shared_;
  ForecastStats stats_;
  // Worker 0 with tangentInBackground: the model and mean the pending tangent is built from.
  // Declared before builder_, whose destructor lets the pending build finish, so that they
  // outlive it.
  std::optional<MechanicalModel> tangentModel_;
  Eigen::VectorXd meanParams_;  // the analysed parameters of the last endStep
  MechanicalState tangentState_;
  std::future<std::shared_ptr<const FrozenTangent>> pendingTangent_;
  int meanChordSteps_ = 0;  // the chord steps of the last static mean's solve (worker 0)
  bool recentred_ = false;  // this frame's reference is already at its own time (recentre)
  std::unique_ptr<BackgroundThread> builder_;  // the thread every background build runs on
};

}  // namespace bcassim
