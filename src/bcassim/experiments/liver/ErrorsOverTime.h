// Validation error over time as thesis Fig. 5.3/5.4 draw it: per step the mean (and max) error
// over the validation points of a forward run against the truth's, then mean ± σ over the steps.
#pragma once
#include <string>
#include <vector>

namespace bcassim {

// Per step 1 .. steps of a run: mean and max over the points of |model - truth|, mm.
struct StepSeries {
  std::vector<double> mean, max;
};

// Summary over the steps, mm.
struct ErrorOverTime {
  double meanMm = 0, meanStdMm = 0;  // per-step mean error: mean ± σ over steps
  double maxMm = 0, maxStdMm = 0;    // per-step max error: mean ± σ over steps
  double peakMm = 0;                 // largest error of any point at any step
  int steps = 0;
};

// Per-step errors of a run's validation tracks (validation.csv of a simulate run, its frame 0 the
// rest state, skipped) against the truth's, on the same time grid. Throws InputError when the
// files differ in frames or points.
StepSeries validationErrorSeries(const std::string& modelCsv, const std::string& truthCsv);

ErrorOverTime summariseErrors(const StepSeries& series);

}  // namespace bcassim
