// The liver experiment end to end (thesis §5.1, Fig. 3.10): prepare the scenario, run the ground
// truth, assimilate the ligament stiffnesses, validate the estimate by a forward run, run the
// fixed-ligament baseline, and compare both with the truth at the inner validation points.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "bcassim/experiments/liver/ErrorsOverTime.h"
#include "bcassim/experiments/liver/LiverScenario.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/SimulationRunner.h"

namespace bcassim {

struct LiverReport {
  LiverScenario scenario;
  SimulationResult truth, baseline;
  AssimilationResult assimilation;          // the filter run (estimates, step times)
  SimulationResult estimatedRun, priorRun;  // forward runs with the final estimates, the prior
  ErrorOverTime estimated, prior, fixed;
  double maxDeformationMm = 0;         // of the truth's validation points
  double finalTumourRadius95Mm = 0;    // mean over tumours at the last step
  double initialTumourRadius95Mm = 0;  // mean over tumours after the first step
  // With the model error estimated from the innovations (InnovationModelError), at the last step.
  double finalTumourTotalRadius95Mm = 0;
  // Fraction of tumour positions over the steps within that radius of the truth (-1: no truth).
  double tumourCoverage = -1;
};

struct LiverCallbacks {
  std::function<void(const std::string& stage)> stage;  // "truth", "estimate", ...
  std::function<void(const std::string& line)> log;     // progress lines of long stages (atlas)
  ProgressCallback simulation;
  AssimilationCallback assimilation;
};

// Runs everything into outDir (subdirectories truth/, estimate/, estimated/, prior/, baseline/;
// "estimated" and "prior" are forward runs with the final estimates and the prior) and writes
// outDir/errors_over_time.csv (step,time_s,estimated_mean_mm,estimated_max_mm,prior_mean_mm,
// prior_max_mm,fixed_mean_mm,fixed_max_mm) and outDir/summary.csv. Throws InputError,
// NumericalError.
// With `resume`, the forward runs that do not depend on the estimates (truth, prior, baseline)
// continue from their checkpoints (simulate --resume); the meshes and scenes are made again
// (deterministically: a checkpoint of other meshes is refused), the assimilation and the run
// with the estimates are redone.
LiverReport runLiverPipeline(const LiverScenarioOptions& options, const std::string& outDir,
                             const LiverCallbacks& callbacks = {}, bool resume = false);

}  // namespace bcassim
