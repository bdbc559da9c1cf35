// One frame of measurements z_{i+1} of eq. 3.1 with its noise covariance V (called R here). Entries
// may be missing (a marker not tracked) and a frame may hold no data at all: then the filter only
// predicts.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace bcassim {

struct Observation {
  // Measured values, as many as the observation operator predicts (ObservationOperator.h; the
  // forecast model's observables by default); empty = no data this step.
  Eigen::VectorXd values;
  // Diagonal of R (sigma^2 per entry, > 0 where present); used when `covariance` is empty.
  Eigen::VectorXd variance;
  // Full R (symmetric positive definite on the present entries); takes precedence if non-empty.
  Eigen::MatrixXd covariance;
  // Which entries were measured; empty = all. Values of missing entries are ignored (may be NaN).
  std::vector<bool> present;

  // A frame without data: the step is a prediction only.
  static Observation none() { return {}; }
  // A complete frame with independent noise of the same sigma on every entry.
  static Observation withSigma(Eigen::VectorXd values, double sigma) {
    Observation y;
    y.variance = Eigen::VectorXd::Constant(values.size(), sigma * sigma);
    y.values = std::move(values);
    return y;
  }
};

}  // namespace bcassim
