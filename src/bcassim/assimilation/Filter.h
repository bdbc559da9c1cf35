// The predict/correct loop of thesis Fig. 3.5 seen from the caller: one step() per time step.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "bcassim/assimilation/FilterStepReport.h"
#include "bcassim/assimilation/Observation.h"

namespace bcassim {

// Everything a filter carries from one step to the next, for checkpoints: matrices (mean,
// covariance or its factors, members) and text (a random generator's state).
struct FilterState {
  std::vector<Eigen::MatrixXd> matrices;
  std::string text;
};

class Filter {
 public:
  virtual ~Filter() = default;
  // Forecasts every sigma point / member one step (in parallel through the executor); with data,
  // linearises the observation operator (FilterOptions::observation) at the forecasts' mean and
  // predicts every forecast's observation through it; corrects with the entries of `y` the
  // operator keeps (none: prediction only) and calls endStep() on the models.
  virtual FilterStepReport step(const Observation& y) = 0;
  // Current mean of the stochastic state [physical; parameters] in the filter's unconstrained
  // space, and its covariance (formed on demand by the reduced and ensemble filters).
  virtual const Eigen::VectorXd& mean() const = 0;
  virtual Eigen::MatrixXd covariance() const = 0;
  // A factor S (n x r) with covariance() = S S^T, of the filter's own rank: the uncertainty of any
  // linear function H x is then (H S)(H S)^T, cheap even when n x n would not fit in memory.
  virtual Eigen::MatrixXd covarianceFactor() const = 0;
  // restoreState(saveState()) on a filter built the same way continues exactly where the first
  // one was. restoreState throws std::invalid_argument when the state does not fit this filter.
  virtual FilterState saveState() const = 0;
  virtual void restoreState(const FilterState& state) = 0;
};

}  // namespace bcassim
