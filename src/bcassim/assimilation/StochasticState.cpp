#include "bcassim/assimilation/StochasticState.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

StochasticState::StochasticState(Eigen::VectorXd physicalMean, Eigen::VectorXd physicalStddev,
                                 std::vector<Parameter> parameters)
    : physicalMean_(std::move(physicalMean)),
      physicalStddev_(std::move(physicalStddev)),
      parameters_(std::move(parameters)) {
  if (physicalStddev_.size() != physicalMean_.size())
    throw InputError(fmt::format("physical state has {} entries but {} standard deviations",
                                 physicalMean_.size(), physicalStddev_.size()));
  if (!physicalMean_.allFinite() || !physicalStddev_.allFinite() ||
      (physicalStddev_.array() < 0).any())
    throw InputError("physical state mean and standard deviations must be finite, sigma >= 0");
  for (const Parameter& p : parameters_) {
    if (!std::isfinite(p.mean) || !(p.stddev > 0) || !std::isfinite(p.stddev))
      throw InputError(fmt::format(
          "parameter '{}': mean must be finite and standard deviation > 0, got {} and {}", p.name,
          p.mean, p.stddev));
    try {
      p.transform.toUnconstrained(p.mean);
    } catch (const InputError& e) {
      throw InputError(fmt::format("parameter '{}': {}", p.name, e.what()));
    }
  }
}

Eigen::VectorXd StochasticState::initialMean() const {
  Eigen::VectorXd x(size());
  x.head(physicalSize()) = physicalMean_;
  for (Eigen::Index i = 0; i < parameterCount(); ++i) {
    const Parameter& p = parameters_[i];
    x[physicalSize() + i] = p.transform.toUnconstrained(p.mean);
  }
  return x;
}

Eigen::VectorXd StochasticState::initialStddev() const {
  Eigen::VectorXd sd(size());
  sd.head(physicalSize()) = physicalStddev_;
  for (Eigen::Index i = 0; i < parameterCount(); ++i) {
    const Parameter& p = parameters_[i];
    sd[physicalSize() + i] = p.transform.stddevToUnconstrained(p.mean, p.stddev);
  }
  return sd;
}

void StochasticState::physicalParameters(const Eigen::Ref<const Eigen::VectorXd>& x,
                                         Eigen::VectorXd& params) const {
  params.resize(parameterCount());
  for (Eigen::Index i = 0; i < parameterCount(); ++i)
    params[i] = parameters_[i].transform.toPhysical(x[physicalSize() + i]);
}

void StochasticState::toReported(const Eigen::VectorXd& x, const Eigen::VectorXd& sd,
                                 Eigen::VectorXd& mean, Eigen::VectorXd& stddev) const {
  mean = x;
  stddev = sd;
  for (Eigen::Index i = 0; i < parameterCount(); ++i) {
    const Eigen::Index k = physicalSize() + i;
    mean[k] = parameters_[i].transform.toPhysical(x[k]);
    stddev[k] = parameters_[i].transform.stddevToPhysical(x[k], sd[k]);
  }
}

}  // namespace bcassim
