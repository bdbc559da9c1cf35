// Options every filter shares: how the forecasts of one step are scheduled and observed.
#pragma once

namespace bcassim {

class ForecastDistribution;
class ObservationOperator;

struct FilterOptions {
  // Run the forecast of the first sigma point / member alone, then the others in parallel, so
  // that a model can factorise during the first and reuse it for the rest (thesis Alg. 4/5).
  bool firstSigmaPointAlone = false;
  // Maps the forecasts' observables to predicted observations, linearised at their mean once per
  // step with data (ObservationOperator.h). Null: the observables are the predictions
  // (DirectObservation). Not owned; must outlive the filter.
  ObservationOperator* observation = nullptr;
  // Passes of the analysis after the first that linearise the observation operator again, at
  // the observables the previous pass analysed, and correct from the same forecasts (an iterated
  // filter for the operator only: no forecast is repeated). For operators that depend on where
  // they are linearised (a point cloud's closest points: each pass is an ICP iteration weighed by
  // the forecast covariance); the identity and marker operators gain nothing. Passes stop early
  // once a pass moves the analysed mean by less than relinearizationTolerance of its analysed
  // spread (Mahalanobis distance under the analysed covariance): the data's resolution, so that
  // correspondences flickering near the robust threshold do not keep the passes going.
  int relinearizations = 0;
  double relinearizationTolerance = 0.1;
  // A step whose forecasts fail (a model step that failed even at its smallest time step: an
  // element inverted by a sigma point far out in the parameters) is redone with every point
  // halfway to the mean, up to this many times (ForecastEnsemble::forecastRetrying). When they
  // are spent (0: at the first failure) the step ends with the model's own error.
  int forecastRetries = 3;
  // Shares each step's forecasts with other processes (ForecastDistribution.h); null: all here.
  // Not owned; must outlive the filter.
  ForecastDistribution* distribution = nullptr;
};

}  // namespace bcassim
