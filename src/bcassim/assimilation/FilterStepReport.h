// What one filter step returns instead of printing: the estimate, its spread, the innovation,
// repairs and timings (SPEC §2 "outputs per step").
#pragma once
#include <Eigen/Core>
#include <string>

namespace bcassim {

struct StepSeconds {
  double forecast = 0.0;    // all sigma-point / member forecasts
  double correction = 0.0;  // analysis (and statistics of the prediction)
  double total = 0.0;       // the whole step, including endStep() on the models
};

struct FilterStepReport {
  // Analysed mean in physical units: the physical part, then the parameters transformed back.
  Eigen::VectorXd mean;
  // Standard deviations of `mean`; parameters pushed through their transform (delta method).
  Eigen::VectorXd stddev;
  // ||y - mean predicted observation|| over the present entries (0 when none).
  double innovationNorm = 0.0;
  // The two sides of E[nu^T nu] = tr(H P H^T) + tr(R) over the present entries, for an adaptive
  // R (InnovationNoiseEstimator): ||y - mean predicted observation||^2, and the trace of the
  // predicted observations' covariance from the sigma points / members, without R. 0 when none.
  double innovationSquaredNorm = 0.0;
  double predictedObservationTrace = 0.0;
  // Observation entries used this step; 0 means the step was a prediction only.
  Eigen::Index observed = 0;
  // Analysis passes after the first that linearised the observation operator again
  // (FilterOptions::relinearizations).
  int relinearizations = 0;
  // Times the sigma points were forecast again about the analysed mean (RoukfOptions::reforecasts).
  int reforecasts = 0;
  // Covariance factorisations repaired with jitter this step, and the largest jitter.
  int covarianceRepairs = 0;
  double largestJitter = 0.0;
  // Times the step's forecasts were redone closer to the mean (FilterOptions::forecastRetries),
  // and the failure that made the first retry (empty when none).
  int forecastHalvings = 0;
  std::string forecastFailure;
  StepSeconds seconds;
};

}  // namespace bcassim
