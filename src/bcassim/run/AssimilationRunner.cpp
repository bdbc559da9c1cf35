// The assimilation run in four phases, each a function below: set-up (forecast models, state
// layout, executor, filter) -> initial state (outputs opened; the prior's step 0, or the
// checkpoint's step) -> filter loop (one filterStep per step) -> outputs (parameters.csv,
// summaries). runValidation follows the same plan with two forward runs instead of a filter.
#include "bcassim/run/AssimilationRunner.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <random>
#include <sstream>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/assimilation/EtkfFilter.h"
#include "bcassim/assimilation/ForecastEnsemble.h"
#include "bcassim/assimilation/InnovationNoiseEstimator.h"
#include "bcassim/assimilation/RoukfFilter.h"
#include "bcassim/assimilation/ThreadPoolExecutor.h"
#include "bcassim/assimilation/UkfFilter.h"
#include "bcassim/coupling/FreeRunModelError.h"
#include "bcassim/coupling/InnovationModelError.h"
#include "bcassim/coupling/MechanicalForecastModel.h"
#include "bcassim/coupling/ParameterForwardRun.h"
#include "bcassim/coupling/PointCloudObservation.h"
#include "bcassim/io/CsvTruncate.h"
#include "bcassim/mechanics/StepFailure.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/run/AssimilationCheckpoint.h"
#include "bcassim/run/AssimilationEstimates.h"
#include "bcassim/run/HiddenPointLog.h"
#include "bcassim/run/OutputFiles.h"
#include "bcassim/run/ValidationLog.h"
#include "bcassim/tracking/PointCloudUnits.h"

namespace bcassim {

namespace {

namespace fs = std::filesystem;

// The scene's assimilation settings, once checked against what the runner needs. The YAML
// loader refuses the same combinations with the file's line; scenes built in code meet them here.
const AssimilationSettings& settingsOf(const Scene& scene) {
  if (!scene.assimilation)
    throw InputError(scene.sourceFile + ": the scene has no assimilation: section");
  const AssimilationSettings& s = *scene.assimilation;
  if (scene.integrator == IntegratorKind::Static && (s.carryPositions || s.carryVelocities))
    throw InputError(scene.sourceFile +
                     ": integrator.type static: every frame is an equilibrium of the parameters, "
                     "so the assimilation estimates parameters only (assimilation.state positions "
                     "and velocities false)");
  if (s.meanTangent && !s.reuseFactorization)
    throw InputError(scene.sourceFile +
                     ": assimilation.reuse_factorization: false does not go with tangent: mean "
                     "(every sigma point steps with the mean's one factorisation)");
  if (s.reuseFactorization && !s.meanTangent && scene.solver.type != "factorized-pcg")
    throw InputError(fmt::format(
        "{}: assimilation.reuse_factorization: needs solver.type factorized-pcg, got {}",
        scene.sourceFile, scene.solver.type));
  if (!scene.hidden.points.empty() && !s.carryPositions)
    throw InputError(scene.sourceFile +
                     ": hidden_points: needs assimilation.state.positions: true (their "
                     "uncertainty comes from the covariance of the node positions)");
  return s;
}

std::string numberOrNan(const std::optional<double>& v) {
  return v ? fmt::format("{:.10g}", *v) : std::string("nan");
}

void writeParameters(const fs::path& path, const std::vector<ParameterResult>& parameters) {
  std::ofstream out = openForWriting(path);
  out << "parameter,initial_mean,initial_stddev,truth,final_mean,final_stddev\n";
  for (const ParameterResult& p : parameters)
    out << fmt::format("{},{:.10g},{:.6g},{},{:.10g},{:.6g}\n", p.name, p.initialMean,
                       p.initialStddev, numberOrNan(p.truth), p.mean, p.stddev);
  flushOrThrow(out, path);
}

std::vector<ParameterResult> initialParameters(const AssimilationSettings& s) {
  std::vector<ParameterResult> out;
  for (const EstimatedParameter& p : s.parameters)
    out.push_back({p.name, p.mean, p.stddev, p.mean, p.stddev, p.truth});
  return out;
}

Eigen::VectorXd initialValues(const AssimilationSettings& s) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(s.parameters.size()));
  for (size_t i = 0; i < s.parameters.size(); ++i)
    v(static_cast<Eigen::Index>(i)) = s.parameters[i].mean;
  return v;
}

std::string describeEstimate(const std::vector<ParameterResult>& parameters) {
  std::string text;
  for (const ParameterResult& p : parameters)
    text += fmt::format("{}{} {:.4g}±{:.2g}", text.empty() ? "" : "  ", p.name, p.mean, p.stddev);
  return text;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Step times and wall time of a finished run into its result.
void finishTimings(const std::vector<double>& stepMs, Clock::time_point started,
                   AssimilationResult& result) {
  result.medianStepMs = median(stepMs);
  for (double ms : stepMs) result.meanStepMs += ms / static_cast<double>(stepMs.size());
  result.wallSeconds = secondsSince(started);
}

AssimilationProgress progressAt(int step, const Scene& scene, Clock::time_point started,
                                bool freeRun, std::string estimate) {
  AssimilationProgress p;
  p.step = step;
  p.steps = scene.steps;
  p.elapsedSeconds = secondsSince(started);
  p.meanStepMs = p.elapsedSeconds * 1e3 / step;
  p.freeRun = freeRun;
  p.estimate = std::move(estimate);
  return p;
}

// The markers of `step` from the scene's tracks file; null when the file has no frame there.
const Eigen::MatrixX3d* trackedFrameAt(const ObservationSettings& o, int step) {
  if (o.pointCloud) return nullptr;  // a point cloud's frames are read by cloudObservationAt
  return o.tracks.present[static_cast<size_t>(step)] ? &o.tracks.frames[static_cast<size_t>(step)]
                                                     : nullptr;
}

// The markers `observed` at `step` (null: none) as the filter sees them: missing markers masked,
// seeded noise added, noise `sigma` assumed (m).
Observation observationAt(const ObservationSettings& o, int step, const Eigen::MatrixX3d* observed,
                          double sigma, std::mt19937_64& rng) {
  if (step > o.untilStep || observed == nullptr) return Observation::none();
  const Eigen::MatrixX3d& frame = *observed;
  Observation y;
  y.values.resize(3 * frame.rows());
  y.present.assign(static_cast<size_t>(y.values.size()), false);
  std::normal_distribution<double> noise(0.0, 1.0);
  bool any = false;
  for (Eigen::Index i = 0; i < frame.rows(); ++i)
    for (int c = 0; c < 3; ++c) {
      // Drawn for every entry, seen or not, so that a marker's noise does not depend on others.
      const double n = o.noiseStddev * noise(rng);
      const Eigen::Index j = 3 * i + c;
      y.values(j) = frame(i, c) + n;
      y.present[static_cast<size_t>(j)] = std::isfinite(frame(i, c));
      any = any || y.present[static_cast<size_t>(j)];
    }
  if (!any) return Observation::none();
  y.variance = Eigen::VectorXd::Constant(y.values.size(), sigma * sigma);
  return y;
}

// The cloud of `step` as the filter sees it: x, y, z of every point with seeded noise added, noise
// `sigma` assumed (m).
Observation cloudObservationAt(const ObservationSettings& o, const std::vector<bool>& usable,
                               int step, double sigma, std::mt19937_64& rng) {
  if (step > o.untilStep || !usable[static_cast<size_t>(step)]) return Observation::none();
  const Eigen::MatrixX3d& frame = o.pointCloud->frames[static_cast<size_t>(step)];
  Observation y;
  y.values.resize(3 * frame.rows());
  std::normal_distribution<double> noise(0.0, 1.0);
  for (Eigen::Index i = 0; i < frame.rows(); ++i)
    for (int c = 0; c < 3; ++c) y.values(3 * i + c) = frame(i, c) + o.noiseStddev * noise(rng);
  y.variance = Eigen::VectorXd::Constant(y.values.size(), sigma * sigma);
  return y;
}

// Process noise per step in the filter's space: the inflation on every parameter plus each
// parameter's random walk (its physical standard deviation per step taken to the unconstrained
// space at its initial mean; the identity for forces). Empty when there is none.
Eigen::VectorXd processVariance(const AssimilationSettings& s, const StochasticState& layout) {
  Eigen::VectorXd process = Eigen::VectorXd::Zero(layout.size());
  const Eigen::Index m = layout.physicalSize();
  for (size_t i = 0; i < s.parameters.size(); ++i) {
    const EstimatedParameter& p = s.parameters[i];
    const double walk = p.randomWalkPerStep > 0
                            ? p.transform.stddevToUnconstrained(p.mean, p.randomWalkPerStep)
                            : 0.0;
    process(m + static_cast<Eigen::Index>(i)) = s.inflation * s.inflation + walk * walk;
  }
  return process.isZero(0.0) ? Eigen::VectorXd() : process;
}

std::unique_ptr<Filter> makeFilter(const AssimilationSettings& s, const StochasticState& layout,
                                   const std::vector<ForecastModel*>& models, Executor& executor,
                                   ObservationOperator* observation,
                                   ForecastDistribution* distribution) {
  const Eigen::VectorXd process = processVariance(s, layout);
  const int relinearizations =
      s.observations.pointCloud ? s.observations.pointCloud->relinearizations : 0;
  switch (s.filter) {
    case FilterKind::Ukf: {
      UkfOptions o;
      o.firstSigmaPointAlone = false;
      o.observation = observation;
      o.relinearizations = relinearizations;
      o.forecastRetries = s.forecastRetries;
      o.distribution = distribution;
      o.sigmaPoints = s.sigmaPoints;
      o.spread = s.sigmaSpread;
      o.processVariance = process;
      return std::make_unique<UkfFilter>(layout, models, executor, o);
    }
    case FilterKind::Roukf: {
      RoukfOptions o;
      o.firstSigmaPointAlone = false;
      o.observation = observation;
      o.relinearizations = relinearizations;
      o.forecastRetries = s.forecastRetries;
      o.distribution = distribution;
      o.sigmaPoints = s.sigmaPoints;
      o.processVariance = process;
      o.reforecasts = s.reforecasts;
      o.reforecastBeyond = s.reforecastBeyond;
      return std::make_unique<RoukfFilter>(layout, models, executor, o);
    }
    case FilterKind::Etkf: {
      EtkfOptions o;
      o.firstSigmaPointAlone = false;
      o.observation = observation;
      o.relinearizations = relinearizations;
      o.forecastRetries = s.forecastRetries;
      o.distribution = distribution;
      o.members = s.members;
      o.seed = s.seed;
      o.processVariance = process;
      return std::make_unique<EtkfFilter>(layout, models, executor, o);
    }
  }
  throw InputError("unknown filter");
}

// ---- Phase 1: set-up --------------------------------------------------------------------------

// What a run is made of: one forecast model per executor worker (models[0] follows the filter's
// mean), the layout of the stochastic state [positions, velocities, parameters], the executor
// and the filter over them.
struct AssimilationSetup {
  std::vector<std::unique_ptr<MechanicalForecastModel>> models;
  std::vector<ForecastModel*> workers;  // models, as the filter takes them
  std::unique_ptr<StochasticState> layout;
  std::unique_ptr<Executor> executor;
  std::unique_ptr<PointCloudObservation> cloud;  // with a point cloud (markers: direct)
  std::vector<bool> cloudUsable;                 // per step: a frame the run can use
  std::unique_ptr<Filter> filter;
  std::vector<std::string> notices;  // the scene's, then the set-up's
};

// The forecast models solve with the scene's solver; with reuse_factorization (factorized-pcg,
// see settingsOf) worker 0 factorises and the others precondition with its factor.
ForecastModelOptions forecastOptions(const Scene& scene) {
  const AssimilationSettings& s = *scene.assimilation;
  ForecastModelOptions options;
  options.layout = {s.carryPositions, s.carryVelocities};
  options.solver = scene.solver.type;
  options.refresh = scene.solver.policy;
  options.shareFactorization = s.reuseFactorization;
  options.meanTangent = s.meanTangent;
  options.tangentRefreshEvery = s.tangentRefreshEvery;
  options.tangentInBackground = s.tangentInBackground;
  options.tangentBackgroundSteps = s.tangentBackgroundSteps;
  options.tangentSinglePrecision = s.tangentSinglePrecision;
  if (scene.integrator == IntegratorKind::Static) options.statics = scene.statics;
  // The mean's equilibrium is solved while the workers wait: it takes all of them (and gives the
  // same bits for any number, so that runs on other thread counts or MPI ranks agree).
  options.meanThreads = s.threads;
  options.observeNodes = s.observations.pointCloud.has_value();
  return options;
}

// The point cloud's operator over the observed surface (the mesh's boundary by default), and
// which frames it can use: a frame whose size says millimetres for a mesh in metres (or the
// other way round) is left out with a notice.
void setUpPointCloud(const Scene& scene, AssimilationSetup& setup) {
  const PointCloudSettings& pc = *scene.assimilation->observations.pointCloud;
  const TetMesh& mesh = *scene.model.mesh;
  const Eigen::MatrixX3i surface = pc.surface.rows() > 0 ? pc.surface : extractBoundary(mesh).F;
  setup.cloud = std::make_unique<PointCloudObservation>(surface, mesh.numNodes(), pc);
  TriMesh rest;
  rest.V = setup.cloud->surfacePositions(scene.model.restPositions());
  setup.cloudUsable = pc.present;
  for (size_t k = 0; k < pc.frames.size(); ++k) {
    if (!pc.present[k]) continue;
    try {
      requireMatchingUnits(pc.frames[k], rest);
    } catch (const InputError& e) {
      setup.notices.push_back(
          fmt::format("{}: {}; step {} is a prediction only", pc.frameNames[k], e.what(), k));
      setup.cloudUsable[k] = false;
    }
  }
}

// `distribution`: the other processes of an MPI run forecast part of each step (null: none).
AssimilationSetup setUp(const Scene& scene, ForecastDistribution* distribution) {
  const AssimilationSettings& s = *scene.assimilation;
  std::vector<ModelParameterTarget> targets;
  std::vector<Parameter> parameters;
  for (const EstimatedParameter& p : s.parameters) {
    targets.push_back(p.target);
    parameters.push_back({p.name, p.mean, p.stddev, p.transform});
  }
  const ForecastModelOptions options = forecastOptions(scene);
  const auto shared = std::make_shared<SharedFactorization>();
  const MechanicalState rest = scene.model.restState();
  AssimilationSetup setup;
  setup.notices = s.notices;
  if (s.observations.pointCloud) setUpPointCloud(scene, setup);
  for (int w = 0; w < s.threads; ++w) {
    setup.models.push_back(std::make_unique<MechanicalForecastModel>(
        scene.model, scene.implicitEuler, scene.markers.points, targets, rest, options, w, shared));
    setup.workers.push_back(setup.models.back().get());
  }
  // The physical state starts known (zero spread): all the prior's uncertainty is in the
  // parameters.
  const Eigen::VectorXd physical = setup.models[0]->packState(rest);
  setup.layout = std::make_unique<StochasticState>(physical, Eigen::VectorXd::Zero(physical.size()),
                                                   parameters);
  if (s.threads > 1)
    setup.executor = std::make_unique<ThreadPoolExecutor>(s.threads);
  else
    setup.executor = std::make_unique<SerialExecutor>();
  setup.filter =
      makeFilter(s, *setup.layout, setup.workers, *setup.executor, setup.cloud.get(), distribution);
  return setup;
}

// What a checkpoint must match: sizes, time step, filter and the estimated parameters.
std::string checkpointKey(const Scene& scene, const StochasticState& layout) {
  const AssimilationSettings& s = *scene.assimilation;
  std::string names;
  for (const EstimatedParameter& p : s.parameters) names += " " + p.name;
  return fmt::format("nodes {} dt {:.17g} filter {} state {} parameters{}",
                     scene.model.mesh->numNodes(), scene.dt(), static_cast<int>(s.filter),
                     layout.size(), names);
}

// ---- Phase 2: outputs opened and the initial state --------------------------------------------

// The run's per-step files, and where its checkpoint goes.
struct AssimilationFiles {
  fs::path dir;
  std::unique_ptr<EstimatesWriter> estimates;
  fs::path filterPath, timingPath, noisePath;
  std::ofstream filter, timing;
  std::ofstream noise;                        // noise.csv, with observations.adaptive_noise
  std::unique_ptr<ValidationLog> validation;  // with assimilation.validation tracks
  std::unique_ptr<HiddenPointLog> hidden;     // with hidden_points
  std::string checkpointPath, checkpointKey;
  fs::path noticesPath;
  std::ofstream notices;  // notices.txt: bad input the run went around, one line each
};

// Opens every per-step file: new with its header, or, resuming from the checkpoint's step,
// cut back to that step and appended to. Writes no row.
AssimilationFiles openFiles(const Scene& scene, const AssimilationSetup& setup, const fs::path& dir,
                            std::optional<int> resumeStep) {
  const AssimilationSettings& s = *scene.assimilation;
  const std::optional<double> cutAt =
      resumeStep ? std::optional<double>(*resumeStep) : std::nullopt;
  AssimilationFiles files;
  files.dir = dir;
  files.checkpointPath = (dir / "checkpoint.bin").string();
  files.checkpointKey = checkpointKey(scene, *setup.layout);
  std::vector<std::string> names;
  for (const EstimatedParameter& p : s.parameters) names.push_back(p.name);
  const std::string estimates = (dir / "estimates.csv").string();
  files.estimates = resumeStep ? std::make_unique<EstimatesWriter>(estimates, names, *resumeStep)
                               : std::make_unique<EstimatesWriter>(estimates, names);
  files.filterPath = dir / "filter.csv";
  files.timingPath = dir / "timing.csv";
  // The cloud columns only with a point cloud: marker runs keep their five columns.
  files.filter = openStepCsv(
      files.filterPath.string(),
      std::string("step,time_s,observed_entries,innovation_norm_m,covariance_repairs") +
          (setup.cloud ? ",cloud_points,cloud_points_used,cloud_median_distance_m,cloud_cutoff_m,"
                         "cloud_relinearizations"
                       : ""),
      cutAt);
  files.timing =
      openStepCsv(files.timingPath.string(),
                  "step,time_s,forecast_ms,correction_ms,total_ms,validation_ms,assembly_cpu_ms,"
                  "solve_cpu_ms,tangent_cpu_ms,linear_iterations,factorizations,tangent_failures,"
                  "tangent_wait_ms,step_retries,reforecasts",
                  cutAt);
  if (s.observations.adaptiveNoise) {
    files.noisePath = dir / "noise.csv";
    files.noise = openStepCsv(files.noisePath.string(),
                              "step,time_s,observed_entries,sigma_m,estimated_sigma_m,"
                              "innovation_squared_norm_m2,predicted_observation_trace_m2",
                              cutAt);
  }
  if (s.validationTruth) files.validation = std::make_unique<ValidationLog>(scene, dir, cutAt);
  if (!scene.hidden.points.empty()) files.hidden = std::make_unique<HiddenPointLog>(dir, cutAt);
  // A resumed run keeps the notices written so far (those of the set-up among them).
  files.noticesPath = dir / "notices.txt";
  files.notices = resumeStep ? std::ofstream(files.noticesPath, std::ios::app)
                             : openForWriting(files.noticesPath);
  if (!resumeStep)
    for (const std::string& line : setup.notices) files.notices << line << '\n';
  flushOrThrow(files.notices, files.noticesPath);
  return files;
}

// What the filter loop carries from one step to the next; a checkpoint saves all of it.
struct FilterLoopState {
  int firstStep = 1;
  std::mt19937_64 rng;  // observation noise
  InnovationModelError modelError;
  FreeRunModelError freeRun;
  // With observations.adaptive_noise: the sigma the next step assumes (else the scene's sigma).
  std::optional<InnovationNoiseEstimator> noise;
  double sigma(const ObservationSettings& o) const { return noise ? noise->sigma() : o.sigma; }
  // With validation tracks: the forward run with the initial parameters, for comparison.
  std::unique_ptr<ParameterForwardRun> initialRun;
  std::vector<double> stepMs;     // wall time of each filter step
  AssimilationResult result;      // the estimate so far, observed steps, tangent failures
  bool cloudMisfitNamed = false;  // a frame the model does not fit has had its notice
};

// A frame whose points lie a median of more than this many sigmas (and more than min_distance)
// from the model's surface is not fitted: the first such frame is named (a background in view
// is the usual cause, and the run would otherwise only show it in filter.csv).
constexpr double kMisfitSigmas = 5.0;

FilterLoopState newLoopState(const Scene& scene, const fs::path& dir) {
  const AssimilationSettings& s = *scene.assimilation;
  FilterLoopState loop;
  loop.rng.seed(s.seed);
  if (const auto& a = s.observations.adaptiveNoise)
    loop.noise.emplace(s.observations.sigma, a->window, a->floor);
  if (s.validationTruth)
    loop.initialRun = std::make_unique<ParameterForwardRun>(scene, s.parameters, initialValues(s));
  loop.result.outDir = dir.string();
  loop.result.steps = scene.steps;
  loop.result.parameters = initialParameters(s);
  return loop;
}

// A new run starts from the prior: its step 0 rows (estimates, hidden points).
FilterLoopState startFromPrior(const Scene& scene, const AssimilationSetup& setup,
                               AssimilationFiles& files) {
  FilterLoopState loop = newLoopState(scene, files.dir);
  loop.result.notices = setup.notices;
  const StochasticState& layout = *setup.layout;
  Eigen::VectorXd mean, sd;
  layout.toReported(layout.initialMean(), layout.initialStddev(), mean, sd);
  files.estimates->write(0, 0.0, mean.tail(layout.parameterCount()),
                         sd.tail(layout.parameterCount()));
  if (files.hidden)
    files.hidden->add(
        0, 0.0,
        predictHiddenPoints(
            scene, *setup.models[0], *setup.filter,
            Eigen::VectorXd::Zero(static_cast<Eigen::Index>(scene.hidden.points.size()))));
  return loop;
}

// The filter and the models as they were after step c.step (read from checkpointPath).
void restoreFilterAndModels(AssimilationSetup& setup, const AssimilationCheckpoint& c,
                            const std::string& checkpointPath) {
  try {
    setup.filter->restoreState(c.filter);
  } catch (const std::invalid_argument&) {
    throw InputError(checkpointPath + ": the filter's state does not fit this scene");
  }
  Eigen::VectorXd params;
  setup.layout->physicalParameters(setup.filter->mean(), params);
  for (const auto& m : setup.models) m->restoreReference(c.reference, params);
}

// A resumed run starts from its checkpoint: filter, models, initial-parameter run, summaries,
// noise generator and the result so far as they were after step c.step.
FilterLoopState resumeFromCheckpoint(const Scene& scene, AssimilationSetup& setup,
                                     AssimilationFiles& files, const AssimilationCheckpoint& c) {
  FilterLoopState loop = newLoopState(scene, files.dir);
  loop.result.notices = setup.notices;
  restoreFilterAndModels(setup, c, files.checkpointPath);
  if (loop.initialRun) loop.initialRun->restore(c.initialRun, c.initialRunSteps);
  if (files.validation) files.validation->restore(c.errorSummaries);
  std::istringstream(c.rng) >> loop.rng;
  loop.modelError.restore(c.innovationSumSquares, c.innovationEntries);
  if (loop.noise && c.noiseVariance > 0) {
    try {
      loop.noise->restore(c.noiseWindow, c.noiseVariance);
    } catch (const InputError&) {
      throw InputError(files.checkpointPath + ": damaged (adaptive noise window)");
    }
  }
  if (c.freeRunLast.size() > 0 && c.freeRunLast.cols() != 3)
    throw InputError(files.checkpointPath + ": damaged (hidden points' free-run positions)");
  loop.freeRun.restore(
      c.motionSumSquares, c.motionEntries, c.freeRunPath.reshaped(),
      c.freeRunLast.size() > 0 ? Eigen::MatrixX3d(c.freeRunLast) : Eigen::MatrixX3d());
  loop.stepMs = c.stepMs;
  loop.result.observedSteps = c.observedSteps;
  loop.result.tangentFailures = c.tangentFailures;
  for (size_t i = 0; i < loop.result.parameters.size(); ++i) {
    loop.result.parameters[i].mean = c.parameters(static_cast<Eigen::Index>(i), 0);
    loop.result.parameters[i].stddev = c.parameters(static_cast<Eigen::Index>(i), 1);
  }
  loop.firstStep = c.step + 1;
  return loop;
}

// ---- Phase 3: the filter loop -----------------------------------------------------------------

// Everything the files hold up to `step`, so that a run stopped later resumes here.
void writeCheckpoint(int step, const AssimilationSetup& setup, const AssimilationFiles& files,
                     const FilterLoopState& loop) {
  AssimilationCheckpoint c;
  c.step = step;
  c.filter = setup.filter->saveState();
  c.reference = setup.models[0]->reference();
  if (loop.initialRun) {
    c.initialRun = loop.initialRun->state();
    c.initialRunSteps = loop.initialRun->steps();
  }
  if (files.validation) c.errorSummaries = files.validation->saved();
  std::ostringstream generator;
  generator << loop.rng;
  c.rng = generator.str();
  c.innovationSumSquares = loop.modelError.sumSquares();
  c.innovationEntries = loop.modelError.entries();
  if (loop.noise) {
    c.noiseWindow = loop.noise->saved();
    c.noiseVariance = loop.noise->variance();
  }
  c.motionSumSquares = loop.freeRun.sumSquares();
  c.motionEntries = loop.freeRun.entries();
  // Without hidden points both are empty: kept 0 x 0, the archive's empty matrix.
  if (loop.freeRun.last().size() > 0) {
    c.freeRunPath = loop.freeRun.path();
    c.freeRunLast = loop.freeRun.last();
  }
  c.stepMs = loop.stepMs;
  c.observedSteps = loop.result.observedSteps;
  c.tangentFailures = loop.result.tangentFailures;
  const auto P = static_cast<Eigen::Index>(loop.result.parameters.size());
  c.parameters.resize(P, 2);
  for (Eigen::Index i = 0; i < P; ++i) {
    const ParameterResult& p = loop.result.parameters[static_cast<size_t>(i)];
    c.parameters.row(i) << p.mean, p.stddev;
  }
  writeAssimilationCheckpoint(files.checkpointPath, files.checkpointKey, c);
}

// A line of notices.txt (flushed at once) and of the run's result.
void addNotice(const std::string& line, AssimilationFiles& files, FilterLoopState& loop) {
  files.notices << line << '\n';
  flushOrThrow(files.notices, files.noticesPath);
  loop.result.notices.push_back(line);
}

// One step: observe (`markers`: the step's markers, null for none) -> filter step (forecast and
// correction) -> log the estimate -> validation and hidden points (published to `stream`) ->
// timing -> checkpoint (at output steps). Every row is flushed.
FilterStepReport filterStep(int step, const Scene& scene, const Eigen::MatrixX3d* markers,
                            const AssimilationStream* stream, AssimilationSetup& setup,
                            AssimilationFiles& files, FilterLoopState& loop) {
  const AssimilationSettings& s = *scene.assimilation;
  const double time = step * scene.dt();
  const double sigma = loop.sigma(s.observations);
  const Observation y =
      setup.cloud ? cloudObservationAt(s.observations, setup.cloudUsable, step, sigma, loop.rng)
                  : observationAt(s.observations, step, markers, sigma, loop.rng);
  FilterStepReport report;
  try {
    report = setup.filter->step(y);
  } catch (const StepFailure& e) {
    // A sigma point's forecast failed even with its step halved to the floor, and again with
    // the points pulled in (assimilation.forecast_retries): the run stops here, with the
    // checkpoint of the last output step to resume from.
    const std::string retried =
        s.forecastRetries == 0
            ? ""
            : fmt::format(" (the last of {} tries, the sigma points at 1/{} of their spread)",
                          s.forecastRetries + 1, 1 << s.forecastRetries);
    throw NumericalError(fmt::format("{}: assimilation step {} (t = {:.6g} s), a forecast: {}{}",
                                     scene.sourceFile, step, time, e.detail(), retried));
  } catch (const NumericalError& e) {
    throw NumericalError(fmt::format("{}: assimilation step {} (t = {:.6g} s): {}",
                                     scene.sourceFile, step, time, e.what()));
  }
  if (report.forecastHalvings > 0) {
    // The step went on closer to the mean: said once per step, with the failure that started it.
    const std::string line = fmt::format(
        "{}: assimilation step {} (t = {:.6g} s): {}; the step's forecasts were redone with the "
        "sigma points at 1/{} of their spread from the mean",
        scene.sourceFile, step, time, report.forecastFailure, 1 << report.forecastHalvings);
    addNotice(line, files, loop);
    if (stream && stream->notice) stream->notice(line);
  }
  ForecastStats cost;
  for (const auto& m : setup.models) cost += m->takeStats();

  const Eigen::Index P = setup.layout->parameterCount();
  const Eigen::VectorXd mean = report.mean.tail(P), sd = report.stddev.tail(P);
  files.estimates->write(step, time, mean, sd);
  for (Eigen::Index i = 0; i < P; ++i) {
    loop.result.parameters[static_cast<size_t>(i)].mean = mean(i);
    loop.result.parameters[static_cast<size_t>(i)].stddev = sd(i);
  }
  if (report.observed > 0) ++loop.result.observedSteps;
  PointCloudStepStats cloud;
  if (setup.cloud && y.values.size() > 0) {
    cloud = setup.cloud->lastStats();
    if (cloud.used == 0) {
      const PointCloudSettings& pc = *s.observations.pointCloud;
      const std::string line = fmt::format(
          "{}: step {} (t = {:.6g} s): fewer than point_cloud.min_points ({}) of its {} points "
          "within {:.3g} mm of the model's surface; a prediction only",
          pc.frameNames[static_cast<size_t>(step)], step, time, pc.minPoints, cloud.points,
          1e3 * cloud.cutoff);
      addNotice(line, files, loop);
    } else if (!loop.cloudMisfitNamed) {
      const PointCloudSettings& pc = *s.observations.pointCloud;
      if (cloud.medianDistance > std::max(kMisfitSigmas * sigma, pc.minCutoff)) {
        const std::string line = fmt::format(
            "{}: step {} (t = {:.6g} s): its points lie a median {:.3g} mm from the model's "
            "surface, more than {:.0f} sigma and min_distance: the model does not fit them; a "
            "background in view (a table, an instrument) as large as the organ's part is kept by "
            "the robust cutoff: set point_cloud.keep_fraction (the organ's share of the view) or "
            "max_distance (m){}. Later frames: cloud_median_distance_m in filter.csv",
            pc.frameNames[static_cast<size_t>(step)], step, time, 1e3 * cloud.medianDistance,
            kMisfitSigmas,
            s.observations.frameTransform
                ? ""
                : "; points in another frame (a camera's) need observations.frame_transform "
                  "(`bcassim register`'s transform.csv)");
        addNotice(line, files, loop);
        loop.cloudMisfitNamed = true;
      }
    }
  }
  files.filter << fmt::format("{},{:.9g},{},{:.6g},{}", step, time, report.observed,
                              report.innovationNorm, report.covarianceRepairs);
  if (setup.cloud)
    files.filter << fmt::format(",{},{},{:.6g},{:.6g},{}", cloud.points, cloud.used,
                                cloud.medianDistance, cloud.cutoff, report.relinearizations);
  files.filter << '\n';
  flushOrThrow(files.filter, files.filterPath);

  if (loop.noise) {
    loop.noise->add(report.innovationSquaredNorm, report.observed,
                    report.predictedObservationTrace);
    files.noise << fmt::format("{},{:.9g},{},{:.9g},{:.9g},{:.9g},{:.9g}\n", step, time,
                               report.observed, sigma, loop.noise->sigma(),
                               report.innovationSquaredNorm, report.predictedObservationTrace);
    flushOrThrow(files.noise, files.noisePath);
  }

  // The hidden points first, and published at once: a live display waits for nothing else.
  loop.modelError.add(report.innovationNorm, static_cast<long>(report.observed));
  if (files.hidden || (stream && stream->publish)) {
    const MechanicalForecastModel& meanModel = *setup.models[0];
    const double q = loop.modelError.variance(loop.sigma(s.observations));
    Eigen::VectorXd variance =
        Eigen::VectorXd::Constant(static_cast<Eigen::Index>(scene.hidden.points.size()), q);
    if (files.hidden) {
      loop.freeRun.add(report.observed > 0,
                       meanModel.positionsOf(scene.markers.points) - scene.markers.rest,
                       meanModel.positionsOf(scene.hidden.points));
      if (s.observations.modelErrorGrows) variance += loop.freeRun.growth(q);
    }
    const std::vector<HiddenPointPrediction> hidden =
        files.hidden ? predictHiddenPoints(scene, meanModel, *setup.filter, variance)
                     : std::vector<HiddenPointPrediction>();
    if (stream && stream->publish) {
      const MechanicalState& m = setup.models[0]->reference();
      stream->publish({step, time, hidden, &m.x, &m.v, mean, sd});
    }
    if (files.hidden) files.hidden->add(step, time, hidden);
  }
  const Clock::time_point v0 = Clock::now();
  if (files.validation) {
    loop.initialRun->step();
    if (files.validation->hasTruth(step))
      files.validation->add(step, time, setup.models[0]->positionsOf(scene.validation.points),
                            loop.initialRun->positionsOf(scene.validation.points));
  }
  const double validationSeconds = secondsSince(v0);

  files.timing << fmt::format(
      "{},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.4g},{},{},{:.6g},{},{}\n",
      step, time, 1e3 * report.seconds.forecast, 1e3 * report.seconds.correction,
      1e3 * report.seconds.total, 1e3 * validationSeconds, 1e3 * cost.assemblySeconds,
      1e3 * cost.solveSeconds, 1e3 * cost.tangentSeconds,
      cost.forecasts > 0 ? static_cast<double>(cost.linearIterations) / cost.forecasts : 0.0,
      cost.factorizations, cost.tangentFailures, 1e3 * cost.tangentWaitSeconds, cost.stepRetries,
      report.reforecasts);
  loop.result.tangentFailures += cost.tangentFailures;
  flushOrThrow(files.timing, files.timingPath);
  loop.stepMs.push_back(1e3 * report.seconds.total);

  if (step % scene.output.every == 0 || step == scene.steps)
    writeCheckpoint(step, setup, files, loop);
  return report;
}

// ---- Phase 4: outputs -------------------------------------------------------------------------

// parameters.csv with the final estimate, errors_summary.csv, and the run's timings.
AssimilationResult finishAssimilation(AssimilationFiles& files, FilterLoopState& loop,
                                      Clock::time_point started) {
  writeParameters(files.dir / "parameters.csv", loop.result.parameters);
  if (files.validation) files.validation->finish(loop.result);
  finishTimings(loop.stepMs, started, loop.result);
  return std::move(loop.result);
}

}  // namespace

AssimilationResult runAssimilation(const Scene& scene, const std::string& outDir,
                                   const AssimilationCallback& progress, bool resume,
                                   const AssimilationStream* stream,
                                   ForecastDistribution* distribution) {
  const Clock::time_point started = Clock::now();
  const AssimilationSettings& s = settingsOf(scene);
  if (!stream && s.observations.streamed)
    throw InputError(scene.sourceFile +
                     ": assimilation.observations.tracks: stream: the markers come from "
                     "`bcassim serve` (OpenIGTLink); to assimilate, name a tracks file");
  if (stream && s.observations.pointCloud)
    throw InputError(scene.sourceFile +
                     ": assimilation.observations.point_cloud: a streamed run takes tracked "
                     "markers (tracks:), not point clouds yet");
  const fs::path dir(outDir);
  createOutputDirectory(dir);

  // 1. Set-up: forecast models, state layout, executor, filter.
  AssimilationSetup setup = setUp(scene, distribution);

  // 2. Outputs opened and the initial state: the prior's step 0, or the checkpoint's step.
  // parameters.csv holds the prior until the run ends (then the final estimate).
  writeParameters(dir / "parameters.csv", initialParameters(s));
  std::optional<AssimilationCheckpoint> checkpoint;
  if (resume)
    checkpoint = readAssimilationCheckpoint((dir / "checkpoint.bin").string(),
                                            checkpointKey(scene, *setup.layout));
  AssimilationFiles files = openFiles(
      scene, setup, dir, checkpoint ? std::optional<int>(checkpoint->step) : std::nullopt);
  FilterLoopState loop = checkpoint ? resumeFromCheckpoint(scene, setup, files, *checkpoint)
                                    : startFromPrior(scene, setup, files);

  // 3. The filter loop.
  for (int step = loop.firstStep; step <= scene.steps; ++step) {
    StreamedFrame streamed;
    if (stream) {
      streamed = stream->frame(step);
      if (streamed.kind == StreamedFrame::Kind::End) break;
    }
    const Eigen::MatrixX3d* markers = !stream ? trackedFrameAt(s.observations, step)
                                      : streamed.kind == StreamedFrame::Kind::Observed
                                          ? &streamed.markers
                                          : nullptr;
    if (distribution) distribution->beginStep(step);
    const FilterStepReport report = filterStep(step, scene, markers, stream, setup, files, loop);
    loop.result.steps = step;
    if (progress)
      progress(progressAt(step, scene, started, report.observed == 0,
                          describeEstimate(loop.result.parameters)));
  }

  // 4. Outputs: parameters.csv with the final estimate, errors_summary.csv, timings.
  return finishAssimilation(files, loop, started);
}

void serveAssimilationForecasts(const Scene& scene, const std::string& outDir, bool resume,
                                const std::function<void(ForecastEnsemble&)>& serve) {
  settingsOf(scene);
  // Phase 1 and the restored checkpoint as runAssimilation has them, so that these models are
  // its models' copies; the filter is built only to read the checkpoint's mean.
  AssimilationSetup setup = setUp(scene, nullptr);
  if (resume) {
    const std::string path = (fs::path(outDir) / "checkpoint.bin").string();
    restoreFilterAndModels(
        setup, readAssimilationCheckpoint(path, checkpointKey(scene, *setup.layout)), path);
  }
  ForecastEnsemble ensemble(*setup.layout, setup.workers, *setup.executor, false);
  serve(ensemble);
}

namespace {

// ---- Validation: a forward run with the final estimates against one with the initial values --

// The last estimate of each of the scene's parameters in estimates.csv, as the result's final
// values.
std::vector<ParameterResult> finalEstimates(const AssimilationSettings& s,
                                            const std::string& estimatesPath) {
  const auto finals = readFinalEstimates(estimatesPath);
  std::vector<ParameterResult> parameters = initialParameters(s);
  for (size_t i = 0; i < s.parameters.size(); ++i) {
    const auto it = finals.find(s.parameters[i].name);
    if (it == finals.end())
      throw InputError(fmt::format("{}: no estimate of parameter '{}' (assimilation.parameters)",
                                   estimatesPath, s.parameters[i].name));
    parameters[i].mean = it->second.mean;
    parameters[i].stddev = it->second.stddev;
  }
  return parameters;
}

Eigen::VectorXd meansOf(const std::vector<ParameterResult>& parameters) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(parameters.size()));
  for (size_t i = 0; i < parameters.size(); ++i)
    v(static_cast<Eigen::Index>(i)) = parameters[i].mean;
  return v;
}

// The two forward runs and what they write.
struct ValidationRuns {
  ParameterForwardRun estimated, initial;
  ValidationLog log;
  fs::path timingPath;
  std::ofstream timing;
  std::vector<double> stepMs;  // wall time of the run with the estimates
};

// One step of both runs, their errors against the truth and their timings.
void validationStep(int step, const Scene& scene, ValidationRuns& runs) {
  const double time = step * scene.dt();
  const Clock::time_point t0 = Clock::now();
  runs.estimated.step();
  const double estimatedSeconds = secondsSince(t0);
  const Clock::time_point t1 = Clock::now();
  runs.initial.step();
  const double initialSeconds = secondsSince(t1);
  if (runs.log.hasTruth(step))
    runs.log.add(step, time, runs.estimated.positionsOf(scene.validation.points),
                 runs.initial.positionsOf(scene.validation.points));
  runs.timing << fmt::format("{},{:.9g},{:.6g},{:.6g}\n", step, time, 1e3 * estimatedSeconds,
                             1e3 * initialSeconds);
  flushOrThrow(runs.timing, runs.timingPath);
  runs.stepMs.push_back(1e3 * estimatedSeconds);
}

}  // namespace

AssimilationResult runValidation(const Scene& scene, const std::string& estimatesPath,
                                 const std::string& outDir, const AssimilationCallback& progress) {
  const Clock::time_point started = Clock::now();
  const AssimilationSettings& s = settingsOf(scene);
  if (!s.validationTruth)
    throw InputError(scene.sourceFile +
                     ": assimilation.validation.tracks: missing (truth of the validation points)");
  AssimilationResult result;
  result.outDir = outDir;
  result.steps = scene.steps;
  result.parameters = finalEstimates(s, estimatesPath);

  const fs::path dir(outDir);
  writeParameters(dir / "parameters.csv", result.parameters);
  ValidationRuns runs{ParameterForwardRun(scene, s.parameters, meansOf(result.parameters)),
                      ParameterForwardRun(scene, s.parameters, initialValues(s)),
                      ValidationLog(scene, dir, std::nullopt), dir / "timing.csv"};
  runs.timing = openForWriting(runs.timingPath);
  runs.timing << "step,time_s,estimated_ms,initial_ms\n";

  const std::string estimate = describeEstimate(result.parameters);
  for (int step = 1; step <= scene.steps; ++step) {
    validationStep(step, scene, runs);
    if (progress) progress(progressAt(step, scene, started, false, estimate));
  }

  runs.log.finish(result);
  finishTimings(runs.stepMs, started, result);
  return result;
}

}  // namespace bcassim
