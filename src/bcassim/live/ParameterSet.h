// The parameters as the filter published them after a frame: mean, covariance and the frame they
// include. Shared read-only between the threads, and replaced whole, never edited in place.
#pragma once
#include <Eigen/Core>

namespace bcassim {

struct ParameterSet {
  // The parameters' mean (n entries, in the filter's units, e.g. N/m).
  Eigen::VectorXd mean;
  // Their covariance, n by n.
  Eigen::MatrixXd covariance;
  // Index of the frame the filter analysed last; -1 for the prior (no frame analysed yet).
  long frame = -1;
  // The analysed model state these parameters go with (the filter's layout, e.g. positions then
  // velocities), for a real-time model to continue from; empty when there is none.
  Eigen::VectorXd state;
  // What else the filter publishes for displays (e.g. hidden points' 95 % radii, m); the engine
  // never reads it.
  Eigen::VectorXd extras;
};

// Throws InputError unless `set` has a non-empty mean and an n by n covariance, n = its mean's
// size, and, when expectedSize >= 0, n = expectedSize. `what` names the set in the message.
void checkParameterSet(const ParameterSet& set, long expectedSize, const char* what);

}  // namespace bcassim
