// Options every filter shares: how the forecasts of one step are scheduled.
#pragma once

namespace bcassim {

struct FilterOptions {
  // Run the forecast of the first sigma point / member alone, then the others in parallel, so
  // that a model can factorise during the first and reuse it for the rest (thesis Alg. 4/5).
  bool firstSigmaPointAlone = false;
};

}  // namespace bcassim
