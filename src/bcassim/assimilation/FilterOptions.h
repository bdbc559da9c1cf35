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
  // Shares each step's forecasts with other processes (ForecastDistribution.h); null: all here.
  // Not owned; must outlive the filter.
  ForecastDistribution* distribution = nullptr;
};

}  // namespace bcassim
