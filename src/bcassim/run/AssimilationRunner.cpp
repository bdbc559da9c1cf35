#include "bcassim/run/AssimilationRunner.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <sstream>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/assimilation/EtkfFilter.h"
#include "bcassim/assimilation/RoukfFilter.h"
#include "bcassim/assimilation/ThreadPoolExecutor.h"
#include "bcassim/assimilation/UkfFilter.h"
#include "bcassim/coupling/InnovationModelError.h"
#include "bcassim/coupling/MechanicalForecastModel.h"
#include "bcassim/coupling/ParameterForwardRun.h"
#include "bcassim/coupling/PointUncertainty.h"
#include "bcassim/io/CsvTruncate.h"
#include "bcassim/io/Files.h"
#include "bcassim/run/AssimilationCheckpoint.h"
#include "bcassim/run/AssimilationEstimates.h"
#include "bcassim/run/ValidationErrors.h"

namespace bcassim {

namespace {

std::ofstream openForWriting(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  std::ofstream out(path);
  if (!out) io::throwWriteError(path.string());
  return out;
}

void flushOrThrow(std::ofstream& out, const std::filesystem::path& path) {
  out.flush();
  if (!out) io::throwWriteError(path.string());
}

const AssimilationSettings& settingsOf(const Scene& scene) {
  if (!scene.assimilation)
    throw InputError(scene.sourceFile + ": the scene has no assimilation: section");
  if (scene.integrator != IntegratorKind::ImplicitEuler)
    throw InputError(scene.sourceFile +
                     ": integrator.type: assimilation needs implicit-euler (the filter steps in "
                     "time)");
  return *scene.assimilation;
}

std::string numberOrNan(const std::optional<double>& v) {
  return v ? fmt::format("{:.10g}", *v) : std::string("nan");
}

void writeParameters(const std::filesystem::path& path,
                     const std::vector<ParameterResult>& parameters) {
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

// What a checkpoint must match: sizes, time step, filter and the estimated parameters.
std::string checkpointKey(const Scene& scene, const StochasticState& layout) {
  const AssimilationSettings& s = *scene.assimilation;
  std::string names;
  for (const EstimatedParameter& p : s.parameters) names += " " + p.name;
  return fmt::format("nodes {} dt {:.17g} filter {} state {} parameters{}",
                     scene.model.mesh->numNodes(), scene.dt(), static_cast<int>(s.filter),
                     layout.size(), names);
}

// Per-step validation errors of the estimated and the initial model against the truth, written
// as errors.csv, with the summaries over all steps and over the free run.
class ValidationLog {
 public:
  ValidationLog(const Scene& scene, const std::filesystem::path& dir,
                std::optional<double> resumeStep)
      : truth_(*scene.assimilation->validationTruth),
        untilStep_(scene.assimilation->observations.untilStep),
        path_(dir / "errors.csv"),
        out_(openStepCsv(path_.string(),
                         "step,time_s,estimated_mean_mm,estimated_max_mm,estimated_mean_pct,"
                         "estimated_max_pct,initial_mean_mm,initial_max_mm,initial_mean_pct,"
                         "initial_max_pct",
                         resumeStep)) {
    D_ = maxDeformation(truth_, scene.validation.rest);
  }

  // For checkpoints: the four accumulators, 4 numbers each.
  Eigen::MatrixXd saved() const {
    Eigen::MatrixXd m(4, 4);
    const ErrorSummary* all[] = {&estimated_[0], &estimated_[1], &initial_[0], &initial_[1]};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) m(i, j) = all[i]->saved()[static_cast<size_t>(j)];
    return m;
  }
  void restore(const Eigen::MatrixXd& m) {
    ErrorSummary* all[] = {&estimated_[0], &estimated_[1], &initial_[0], &initial_[1]};
    for (int i = 0; i < 4; ++i) all[i]->restore({m(i, 0), m(i, 1), m(i, 2), m(i, 3)});
  }

  bool hasTruth(int step) const { return truth_.present[static_cast<size_t>(step)]; }

  void add(int step, double time, const Eigen::MatrixX3d& estimated,
           const Eigen::MatrixX3d& initial) {
    const Eigen::MatrixX3d& truth = truth_.frames[static_cast<size_t>(step)];
    const StepError e = stepError(estimated, truth);
    const StepError i = stepError(initial, truth);
    if (e.points == 0) return;
    const bool free = step > untilStep_;
    estimated_[0].add(e);
    initial_[0].add(i);
    if (free) {
      estimated_[1].add(e);
      initial_[1].add(i);
    }
    out_ << fmt::format("{},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", step,
                        time, 1e3 * e.mean, 1e3 * e.max, percent(e.mean), percent(e.max),
                        1e3 * i.mean, 1e3 * i.max, percent(i.mean), percent(i.max));
    flushOrThrow(out_, path_);
  }

  // Fills the result and writes errors_summary.csv.
  void finish(AssimilationResult& result) const {
    result.validated = true;
    result.maxDeformationM = D_;
    result.estimated = {summary(estimated_[0]), summary(estimated_[1])};
    result.initial = {summary(initial_[0]), summary(initial_[1])};
    const std::filesystem::path path = path_.parent_path() / "errors_summary.csv";
    std::ofstream out = openForWriting(path);
    out << "run,phase,steps,mean_pct,max_pct,mean_mm,max_mm,max_deformation_mm\n";
    const std::pair<const char*, const RunErrors*> runs[] = {{"estimated", &result.estimated},
                                                             {"initial", &result.initial}};
    for (const auto& [name, errors] : runs)
      for (const auto& [phase, e] :
           {std::pair<const char*, ErrorResult>{"all", errors->all},
            std::pair<const char*, ErrorResult>{"free_run", errors->freeRun}})
        out << fmt::format("{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", name, phase, e.steps,
                           e.meanPercent, e.maxPercent, 1e3 * e.meanM, 1e3 * e.maxM, 1e3 * D_);
    flushOrThrow(out, path);
  }

 private:
  double percent(double m) const {
    if (D_ > 0) return 100 * m / D_;
    return m > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  }
  ErrorResult summary(const ErrorSummary& s) const {
    return {s.steps(), s.meanM(), s.maxM(), percent(s.meanM()), percent(s.maxM())};
  }

  const TrackFrames& truth_;
  int untilStep_;
  std::filesystem::path path_;
  std::ofstream out_;
  double D_ = 0.0;
  ErrorSummary estimated_[2], initial_[2];
};

// Every step, the predicted position of each hidden point (tumour) and its uncertainty from the
// filter's covariance, written as hidden_points.csv.
class HiddenPointLog {
 public:
  HiddenPointLog(const Scene& scene, const std::filesystem::path& dir,
                 std::optional<double> resumeStep)
      : scene_(scene),
        path_(dir / "hidden_points.csv"),
        out_(openStepCsv(path_.string(),
                         "step,time_s,point,x_m,y_m,z_m,sigma_x_m,sigma_y_m,sigma_z_m,radius95_m,"
                         "model_error_sigma_m,radius95_total_m",
                         resumeStep)) {}

  // modelErrorVariance: q (m^2) of InnovationModelError, added isotropically to the covariance
  // for radius95_total (the eigenvalues shift by q).
  void add(int step, double time, const MechanicalForecastModel& mean, const Filter& filter,
           double modelErrorVariance) {
    const Eigen::MatrixX3d p = mean.positionsOf(scene_.hidden.points);
    const std::vector<PointUncertainty> u =
        pointUncertainty(*scene_.model.mesh, scene_.hidden.points, filter.covarianceFactor());
    for (size_t i = 0; i < u.size(); ++i) {
      const auto r = static_cast<Eigen::Index>(i);
      // sqrt(chi2 (lambda_max + q)) with radius95 = sqrt(chi2 lambda_max)
      const double total =
          std::sqrt(u[i].radius95 * u[i].radius95 + kChiSquare3At95 * modelErrorVariance);
      out_ << fmt::format(
          "{},{:.9g},{},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", step,
          time, i, p(r, 0), p(r, 1), p(r, 2), u[i].sigma(0), u[i].sigma(1), u[i].sigma(2),
          u[i].radius95, std::sqrt(modelErrorVariance), total);
    }
    flushOrThrow(out_, path_);
    last_ = u;
  }
  const std::vector<PointUncertainty>& last() const { return last_; }

 private:
  const Scene& scene_;
  std::filesystem::path path_;
  std::ofstream out_;
  std::vector<PointUncertainty> last_;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// The frame of `step` as the filter sees it: missing markers masked, seeded noise added.
Observation observationAt(const ObservationSettings& o, int step, std::mt19937_64& rng) {
  if (step > o.untilStep || !o.tracks.present[static_cast<size_t>(step)])
    return Observation::none();
  const Eigen::MatrixX3d& frame = o.tracks.frames[static_cast<size_t>(step)];
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
  y.variance = Eigen::VectorXd::Constant(y.values.size(), o.sigma * o.sigma);
  return y;
}

std::unique_ptr<Filter> makeFilter(const AssimilationSettings& s, const StochasticState& layout,
                                   const std::vector<ForecastModel*>& models, Executor& executor) {
  Eigen::VectorXd process;
  if (s.inflation > 0) {
    process = Eigen::VectorXd::Zero(layout.size());
    process.tail(layout.parameterCount()).setConstant(s.inflation * s.inflation);
  }
  switch (s.filter) {
    case FilterKind::Ukf: {
      UkfOptions o;
      o.firstSigmaPointAlone = false;
      o.sigmaPoints = s.sigmaPoints;
      o.spread = s.sigmaSpread;
      o.processVariance = process;
      return std::make_unique<UkfFilter>(layout, models, executor, o);
    }
    case FilterKind::Roukf: {
      RoukfOptions o;
      o.firstSigmaPointAlone = false;
      o.sigmaPoints = s.sigmaPoints;
      return std::make_unique<RoukfFilter>(layout, models, executor, o);
    }
    case FilterKind::Etkf: {
      EtkfOptions o;
      o.firstSigmaPointAlone = false;
      o.members = s.members;
      o.seed = s.seed;
      o.processVariance = process;
      return std::make_unique<EtkfFilter>(layout, models, executor, o);
    }
  }
  throw InputError("unknown filter");
}

}  // namespace

AssimilationResult runAssimilation(const Scene& scene, const std::string& outDir,
                                   const AssimilationCallback& progress, bool resume) {
  const Clock::time_point started = Clock::now();
  const AssimilationSettings& s = settingsOf(scene);
  const std::filesystem::path dir(outDir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(outDir + ": cannot create directory (" + ec.message() + ")");

  // One forecast model per executor worker; with reuse, worker 0 factorises and shares.
  std::vector<ModelParameterTarget> targets;
  std::vector<Parameter> parameters;
  for (const EstimatedParameter& p : s.parameters) {
    targets.push_back(p.target);
    parameters.push_back({p.name, p.mean, p.stddev, p.transform});
  }
  ForecastModelOptions options;
  options.layout = {s.carryPositions, s.carryVelocities};
  options.solver = s.reuseFactorization ? "factorized-pcg" : scene.solver.type;
  options.refresh = scene.solver.policy;
  options.shareFactorization = s.reuseFactorization;
  options.meanTangent = s.meanTangent;
  options.tangentRefreshEvery = s.tangentRefreshEvery;
  options.tangentInBackground = s.tangentInBackground;
  const auto shared = std::make_shared<SharedFactorization>();
  const MechanicalState rest = scene.model.restState();
  std::vector<std::unique_ptr<MechanicalForecastModel>> models;
  std::vector<ForecastModel*> workers;
  for (int w = 0; w < s.threads; ++w) {
    models.push_back(std::make_unique<MechanicalForecastModel>(
        scene.model, scene.implicitEuler, scene.markers.points, targets, rest, options, w, shared));
    workers.push_back(models.back().get());
  }
  const Eigen::VectorXd physical = models[0]->packState(rest);
  const StochasticState layout(physical, Eigen::VectorXd::Zero(physical.size()), parameters);
  std::unique_ptr<Executor> executor;
  if (s.threads > 1)
    executor = std::make_unique<ThreadPoolExecutor>(s.threads);
  else
    executor = std::make_unique<SerialExecutor>();
  std::unique_ptr<Filter> filter = makeFilter(s, layout, workers, *executor);

  AssimilationResult result;
  result.outDir = outDir;
  result.steps = scene.steps;
  result.parameters = initialParameters(s);
  writeParameters(dir / "parameters.csv", result.parameters);

  const std::string checkpointPath = (dir / "checkpoint.bin").string();
  const std::string key = checkpointKey(scene, layout);
  std::optional<AssimilationCheckpoint> resumed;
  if (resume) resumed = readAssimilationCheckpoint(checkpointPath, key);
  const std::optional<double> resumeStep =
      resumed ? std::optional<double>(resumed->step) : std::nullopt;

  std::vector<std::string> names;
  for (const EstimatedParameter& p : s.parameters) names.push_back(p.name);
  std::unique_ptr<EstimatesWriter> estimates;
  if (resumeStep) {
    estimates =
        std::make_unique<EstimatesWriter>((dir / "estimates.csv").string(), names, resumed->step);
  } else {
    estimates = std::make_unique<EstimatesWriter>((dir / "estimates.csv").string(), names);
    Eigen::VectorXd mean, sd;
    layout.toReported(layout.initialMean(), layout.initialStddev(), mean, sd);
    estimates->write(0, 0.0, mean.tail(layout.parameterCount()), sd.tail(layout.parameterCount()));
  }
  const std::filesystem::path filterPath = dir / "filter.csv", timingPath = dir / "timing.csv";
  std::ofstream filterCsv =
      openStepCsv(filterPath.string(),
                  "step,time_s,observed_entries,innovation_norm_m,covariance_repairs", resumeStep);
  std::ofstream timing =
      openStepCsv(timingPath.string(),
                  "step,time_s,forecast_ms,correction_ms,total_ms,validation_ms,assembly_cpu_ms,"
                  "solve_cpu_ms,tangent_cpu_ms,linear_iterations,factorizations,tangent_failures,"
                  "tangent_wait_ms",
                  resumeStep);

  std::unique_ptr<ValidationLog> validation;
  std::unique_ptr<ParameterForwardRun> initialRun;
  if (s.validationTruth) {
    validation = std::make_unique<ValidationLog>(scene, dir, resumeStep);
    initialRun = std::make_unique<ParameterForwardRun>(scene, s.parameters, initialValues(s));
  }

  std::unique_ptr<HiddenPointLog> hidden;
  if (!scene.hidden.points.empty()) {
    if (!s.carryPositions)
      throw InputError(scene.sourceFile +
                       ": hidden_points: needs assimilation.state.positions: true (their "
                       "uncertainty comes from the covariance of the node positions)");
    hidden = std::make_unique<HiddenPointLog>(scene, dir, resumeStep);
    if (!resumeStep) hidden->add(0, 0.0, *models[0], *filter, 0.0);
  }

  std::mt19937_64 rng(s.seed);
  std::vector<double> stepMs;
  InnovationModelError modelError;
  int firstStep = 1;
  if (resumed) {
    const AssimilationCheckpoint& c = *resumed;
    try {
      filter->restoreState(c.filter);
    } catch (const std::invalid_argument&) {
      throw InputError(checkpointPath + ": the filter's state does not fit this scene");
    }
    Eigen::VectorXd params;
    layout.physicalParameters(filter->mean(), params);
    for (const auto& m : models) m->restoreReference(c.reference, params);
    if (initialRun) initialRun->restore(c.initialRun, c.initialRunSteps);
    if (validation) validation->restore(c.errorSummaries);
    std::istringstream(c.rng) >> rng;
    modelError.restore(c.innovationSumSquares, c.innovationEntries);
    stepMs = c.stepMs;
    result.observedSteps = c.observedSteps;
    result.tangentFailures = c.tangentFailures;
    for (size_t i = 0; i < result.parameters.size(); ++i) {
      result.parameters[i].mean = c.parameters(static_cast<Eigen::Index>(i), 0);
      result.parameters[i].stddev = c.parameters(static_cast<Eigen::Index>(i), 1);
    }
    firstStep = c.step + 1;
  }
  const Eigen::Index P = layout.parameterCount();
  for (int step = firstStep; step <= scene.steps; ++step) {
    const double time = step * scene.dt();
    const Observation y = observationAt(s.observations, step, rng);
    const FilterStepReport report = filter->step(y);
    ForecastStats cost;
    for (const auto& m : models) cost += m->takeStats();
    const Eigen::VectorXd mean = report.mean.tail(P), sd = report.stddev.tail(P);
    estimates->write(step, time, mean, sd);
    for (Eigen::Index i = 0; i < P; ++i) {
      result.parameters[static_cast<size_t>(i)].mean = mean(i);
      result.parameters[static_cast<size_t>(i)].stddev = sd(i);
    }
    if (report.observed > 0) ++result.observedSteps;
    filterCsv << fmt::format("{},{:.9g},{},{:.6g},{}\n", step, time, report.observed,
                             report.innovationNorm, report.covarianceRepairs);
    flushOrThrow(filterCsv, filterPath);

    const Clock::time_point v0 = Clock::now();
    if (validation) {
      initialRun->step();
      if (validation->hasTruth(step))
        validation->add(step, time, models[0]->positionsOf(scene.validation.points),
                        initialRun->positionsOf(scene.validation.points));
    }
    modelError.add(report.innovationNorm, static_cast<long>(report.observed));
    if (hidden)
      hidden->add(step, time, *models[0], *filter, modelError.variance(s.observations.sigma));
    const double validationSeconds = secondsSince(v0);
    timing << fmt::format(
        "{},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.4g},{},{},{:.6g}\n", step,
        time, 1e3 * report.seconds.forecast, 1e3 * report.seconds.correction,
        1e3 * report.seconds.total, 1e3 * validationSeconds, 1e3 * cost.assemblySeconds,
        1e3 * cost.solveSeconds, 1e3 * cost.tangentSeconds,
        cost.forecasts > 0 ? static_cast<double>(cost.linearIterations) / cost.forecasts : 0.0,
        cost.factorizations, cost.tangentFailures, 1e3 * cost.tangentWaitSeconds);
    result.tangentFailures += cost.tangentFailures;
    flushOrThrow(timing, timingPath);
    stepMs.push_back(1e3 * report.seconds.total);
    if (step % scene.output.every == 0 || step == scene.steps) {
      // Every file above holds this step: a run stopped later resumes here.
      AssimilationCheckpoint c;
      c.step = step;
      c.filter = filter->saveState();
      c.reference = models[0]->reference();
      if (initialRun) {
        c.initialRun = initialRun->state();
        c.initialRunSteps = initialRun->steps();
      }
      if (validation) c.errorSummaries = validation->saved();
      std::ostringstream generator;
      generator << rng;
      c.rng = generator.str();
      c.innovationSumSquares = modelError.sumSquares();
      c.innovationEntries = modelError.entries();
      c.stepMs = stepMs;
      c.observedSteps = result.observedSteps;
      c.tangentFailures = result.tangentFailures;
      c.parameters.resize(P, 2);
      for (Eigen::Index i = 0; i < P; ++i) c.parameters.row(i) << mean(i), sd(i);
      writeAssimilationCheckpoint(checkpointPath, key, c);
    }

    if (progress) {
      AssimilationProgress p;
      p.step = step;
      p.steps = scene.steps;
      p.elapsedSeconds = secondsSince(started);
      p.meanStepMs = p.elapsedSeconds * 1e3 / step;
      p.freeRun = report.observed == 0;
      p.estimate = describeEstimate(result.parameters);
      progress(p);
    }
  }
  writeParameters(dir / "parameters.csv", result.parameters);
  if (validation) validation->finish(result);
  result.medianStepMs = median(stepMs);
  for (double ms : stepMs) result.meanStepMs += ms / static_cast<double>(stepMs.size());
  result.wallSeconds = secondsSince(started);
  return result;
}

AssimilationResult runValidation(const Scene& scene, const std::string& estimatesPath,
                                 const std::string& outDir, const AssimilationCallback& progress) {
  const Clock::time_point started = Clock::now();
  const AssimilationSettings& s = settingsOf(scene);
  if (!s.validationTruth)
    throw InputError(scene.sourceFile +
                     ": assimilation.validation.tracks: missing (truth of the validation points)");
  const auto finals = readFinalEstimates(estimatesPath);
  AssimilationResult result;
  result.outDir = outDir;
  result.steps = scene.steps;
  result.parameters = initialParameters(s);
  Eigen::VectorXd values(static_cast<Eigen::Index>(s.parameters.size()));
  for (size_t i = 0; i < s.parameters.size(); ++i) {
    const auto it = finals.find(s.parameters[i].name);
    if (it == finals.end())
      throw InputError(fmt::format("{}: no estimate of parameter '{}' (assimilation.parameters)",
                                   estimatesPath, s.parameters[i].name));
    values(static_cast<Eigen::Index>(i)) = it->second.mean;
    result.parameters[i].mean = it->second.mean;
    result.parameters[i].stddev = it->second.stddev;
  }
  const std::filesystem::path dir(outDir);
  writeParameters(dir / "parameters.csv", result.parameters);
  ValidationLog validation(scene, dir, std::nullopt);
  ParameterForwardRun estimated(scene, s.parameters, values);
  ParameterForwardRun initial(scene, s.parameters, initialValues(s));
  const std::filesystem::path timingPath = dir / "timing.csv";
  std::ofstream timing = openForWriting(timingPath);
  timing << "step,time_s,estimated_ms,initial_ms\n";
  std::vector<double> stepMs;
  const std::string estimate = describeEstimate(result.parameters);
  for (int step = 1; step <= scene.steps; ++step) {
    const double time = step * scene.dt();
    const Clock::time_point t0 = Clock::now();
    estimated.step();
    const double estimatedSeconds = secondsSince(t0);
    const Clock::time_point t1 = Clock::now();
    initial.step();
    const double initialSeconds = secondsSince(t1);
    if (validation.hasTruth(step))
      validation.add(step, time, estimated.positionsOf(scene.validation.points),
                     initial.positionsOf(scene.validation.points));
    timing << fmt::format("{},{:.9g},{:.6g},{:.6g}\n", step, time, 1e3 * estimatedSeconds,
                          1e3 * initialSeconds);
    flushOrThrow(timing, timingPath);
    stepMs.push_back(1e3 * estimatedSeconds);
    if (progress) {
      AssimilationProgress p;
      p.step = step;
      p.steps = scene.steps;
      p.elapsedSeconds = secondsSince(started);
      p.meanStepMs = p.elapsedSeconds * 1e3 / step;
      p.estimate = estimate;
      progress(p);
    }
  }
  validation.finish(result);
  result.medianStepMs = median(stepMs);
  for (double ms : stepMs) result.meanStepMs += ms / static_cast<double>(stepMs.size());
  result.wallSeconds = secondsSince(started);
  return result;
}

}  // namespace bcassim
