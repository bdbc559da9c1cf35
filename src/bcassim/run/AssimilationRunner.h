// Runs a scene's assimilation: section (thesis Fig. 3.10, steps 2 and 3): the Kalman filter
// estimating the parameters from the observed tracks, and the validation of an estimate against
// the truth tracks of the validation points. Writes CSV files per step; never prints.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bcassim/assimilation/ForecastDistribution.h"
#include "bcassim/assimilation/ForecastEnsemble.h"
#include "bcassim/run/AssimilationStream.h"
#include "bcassim/scene/Scene.h"

namespace bcassim {

// Where a run stands, reported after every step.
struct AssimilationProgress {
  int step = 0, steps = 0;
  double elapsedSeconds = 0;  // since the run started
  double meanStepMs = 0;      // mean wall time of a step so far
  bool freeRun = false;       // assimilate: this step used no observation
  std::string estimate;       // the current estimate, e.g. "E_0 7.98e+03±41"
};
using AssimilationCallback = std::function<void(const AssimilationProgress&)>;

struct ParameterResult {
  std::string name;
  double initialMean = 0.0, initialStddev = 0.0;
  double mean = 0.0, stddev = 0.0;  // final estimate (validate: the values it ran with)
  std::optional<double> truth;
};

// Validation errors of one run over a set of steps (thesis Tables 3.1-3.5).
struct ErrorResult {
  int steps = 0;  // steps with truth; 0: nothing measured
  double meanM = 0.0, maxM = 0.0;
  double meanPercent = 0.0, maxPercent = 0.0;  // relative to the truth's maximal deformation
};

struct RunErrors {
  ErrorResult all;      // every step with truth
  ErrorResult freeRun;  // steps after observations.until_step
};

struct AssimilationResult {
  std::string outDir;
  int steps = 0;
  int observedSteps = 0;  // steps whose correction used observations
  std::vector<ParameterResult> parameters;
  bool validated = false;        // the scene gives validation tracks
  double maxDeformationM = 0.0;  // D of the truth's validation points
  RunErrors estimated;  // assimilate: the filter's mean model; validate: the final parameters
  RunErrors initial;    // forward run with the initial parameters
  double medianStepMs = 0.0, meanStepMs = 0.0;
  double wallSeconds = 0.0;
  int tangentFailures = 0;  // tangent: mean — mean tangents not positive definite (old one kept)
  // Bad input the run went around (frames left out, points dropped), one line each, as written
  // to notices.txt: for the caller to show.
  std::vector<std::string> notices;
};

// Assimilates scene.assimilation (which must be set) over scene.steps steps, writing to outDir:
//   parameters.csv  parameter,initial_mean,initial_stddev,truth,final_mean,final_stddev
//   estimates.csv   step,time_s,parameter,mean,stddev (step 0 = prior)
//   filter.csv      step,time_s,observed_entries,innovation_norm_m,covariance_repairs, and
//                   with a point cloud cloud_points,cloud_points_used,cloud_median_distance_m,
//                   cloud_cutoff_m
//   notices.txt     bad input the run went around, one line each (AssimilationResult::notices)
//   timing.csv      step,time_s,forecast_ms,correction_ms,total_ms,validation_ms
//   errors.csv, errors_summary.csv  with validation tracks (docs/assimilation-format.md)
// Per-step files are flushed every step. Throws InputError (files), NumericalError (divergence).
//   checkpoint.bin  the run's state at every output step (output.every), replaced atomically;
//                   with `resume` the run continues from it: the CSV files are cut back to its
//                   step and appended to (AssimilationCheckpoint.h).
// With `stream` (bcassim serve) the markers of each step come from stream->frame instead of the
// tracks file (which is not read), the run ends early when it says so, and every step's hidden
// points and mesh go to stream->publish; the files are the same. Not with a point cloud.
// With `distribution` (an MPI run's rank 0, distributed/) the other processes forecast part of
// every step, each running serveAssimilationForecasts; the files are the same, except that
// timing.csv's forecast costs count this process's forecasts only.
AssimilationResult runAssimilation(const Scene& scene, const std::string& outDir,
                                   const AssimilationCallback& progress = {}, bool resume = false,
                                   const AssimilationStream* stream = nullptr,
                                   ForecastDistribution* distribution = nullptr);

// The forecasting half of runAssimilation, for a process that runs no filter (an MPI worker
// rank): the same models and layout as runAssimilation builds (resumed from outDir's checkpoint
// with `resume`) handed to `serve` as a ForecastEnsemble, which answers the filter's process
// until it is done. Writes nothing. Throws InputError as runAssimilation does.
void serveAssimilationForecasts(const Scene& scene, const std::string& outDir, bool resume,
                                const std::function<void(ForecastEnsemble&)>& serve);

// Forward run over the whole horizon with the last values of estimates.csv (estimatesPath),
// compared with the truth validation tracks and with the initial parameters; writes
// parameters.csv, errors.csv, errors_summary.csv and timing.csv to outDir.
AssimilationResult runValidation(const Scene& scene, const std::string& estimatesPath,
                                 const std::string& outDir,
                                 const AssimilationCallback& progress = {});

}  // namespace bcassim
