// Layout of the stochastic state a filter estimates: x = [physical part; parameters], kept apart
// from the model's mechanical state (thesis §3.3). Parameters live in their unconstrained space.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "bcassim/assimilation/ParameterTransform.h"

namespace bcassim {

// One estimated scalar. Sharing is the caller's business: one Parameter may set the stiffness of a
// whole group of springs; the filter only sees the scalar.
struct Parameter {
  std::string name;     // for the caller's reports; the filter does not read it
  double mean = 0.0;    // initial physical value
  double stddev = 0.0;  // initial physical standard deviation, > 0
  ParameterTransform transform;
};

// x has physicalSize() entries the model advances (positions, velocities: may be 0) followed by
// parameterCount() unconstrained parameters u, with physical values transform.toPhysical(u).
// The initial covariance is diagonal: physicalStddev^2, then each parameter's sigma pushed into u.
class StochasticState {
 public:
  // physicalStddev has the size of physicalMean; entries may be 0 (known exactly at start).
  // Throws InputError on size mismatch, negative sigma, a parameter sigma <= 0 or a mean outside
  // the range of its transform.
  StochasticState(Eigen::VectorXd physicalMean, Eigen::VectorXd physicalStddev,
                  std::vector<Parameter> parameters);

  Eigen::Index physicalSize() const { return physicalMean_.size(); }
  Eigen::Index parameterCount() const { return static_cast<Eigen::Index>(parameters_.size()); }
  Eigen::Index size() const { return physicalSize() + parameterCount(); }
  const std::vector<Parameter>& parameters() const { return parameters_; }

  // Initial mean and standard deviation of x in the filter's (unconstrained) space.
  Eigen::VectorXd initialMean() const;
  Eigen::VectorXd initialStddev() const;

  // Physical parameter values of the stochastic state x (size()).
  void physicalParameters(const Eigen::Ref<const Eigen::VectorXd>& x,
                          Eigen::VectorXd& params) const;
  // x and its standard deviations as reported: physical part unchanged, parameters transformed.
  void toReported(const Eigen::VectorXd& x, const Eigen::VectorXd& sd, Eigen::VectorXd& mean,
                  Eigen::VectorXd& stddev) const;

 private:
  Eigen::VectorXd physicalMean_;
  Eigen::VectorXd physicalStddev_;
  std::vector<Parameter> parameters_;
};

}  // namespace bcassim
