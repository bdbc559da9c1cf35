#include "bcassim/assimilation/InnovationNoiseEstimator.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

InnovationNoiseEstimator::InnovationNoiseEstimator(double initialSigma, int window, double floor)
    : initialVariance_(initialSigma * initialSigma),
      window_(window),
      floorVariance_(floor * floor),
      variance_(initialVariance_) {
  if (window < 1)
    throw InputError(fmt::format("adaptive noise window must be >= 1 step, got {}", window));
  if (!(floor > 0.0) || !std::isfinite(initialSigma) || !(floor <= initialSigma))
    throw InputError(
        fmt::format("adaptive noise floor must be > 0 and <= the initial sigma ({}), got {}",
                    initialSigma, floor));
}

double InnovationNoiseEstimator::sigma() const { return std::sqrt(variance_); }

void InnovationNoiseEstimator::add(double innovationSquaredNorm, Eigen::Index entries,
                                   double predictedObservationTrace) {
  if (entries <= 0) return;
  if (!std::isfinite(innovationSquaredNorm) || !std::isfinite(predictedObservationTrace))
    return;  // a step the filter could not measure says nothing about the noise
  steps_.push_back({innovationSquaredNorm, static_cast<double>(entries),
                    std::max(0.0, predictedObservationTrace)});
  while (static_cast<int>(steps_.size()) > window_) steps_.pop_front();
  update();
}

// The likelihood equation solved by its fixed point: sigma^2 = sum w_k m_k s_k / sum w_k m_k with
// w_k = 1 / (t_k / m_k + sigma^2)^2, the window's missing steps counted with s = sigma_0^2 and
// t = 0, starting from the last estimate (a few iterations: the weights change little from one
// step to the next).
void InnovationNoiseEstimator::update() {
  double entries = 0.0;
  for (const Step& k : steps_) entries += k.entries;
  const auto k = static_cast<double>(steps_.size());
  const double missingEntries = k > 0 ? (window_ - k) * entries / k : 1.0;
  double s = std::max(variance_, floorVariance_);
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double w0 = 1.0 / (s * s);
    double numerator = missingEntries * w0 * initialVariance_;
    double denominator = missingEntries * w0;
    for (const Step& step : steps_) {
      const double spread = step.trace / step.entries + s;
      const double w = 1.0 / (spread * spread);
      numerator += w * (step.squaredNorm - step.trace);
      denominator += w * step.entries;
    }
    const double next = std::max(floorVariance_, numerator / denominator);
    const bool converged = std::abs(next - s) <= 1e-12 * s;
    s = next;
    if (converged) {
      variance_ = s;
      return;
    }
  }
  // No fixed point within 100 iterations: the unweighted estimate, which needs none.
  double numerator = missingEntries * initialVariance_, denominator = missingEntries;
  for (const Step& step : steps_) {
    numerator += step.squaredNorm - step.trace;
    denominator += step.entries;
  }
  variance_ = std::max(floorVariance_, numerator / denominator);
}

Eigen::MatrixXd InnovationNoiseEstimator::saved() const {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(steps_.size()), 3);
  for (size_t i = 0; i < steps_.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) << steps_[i].squaredNorm, steps_[i].entries,
        steps_[i].trace;
  return out;
}

void InnovationNoiseEstimator::restore(const Eigen::MatrixXd& window, double variance) {
  if ((window.size() > 0 && window.cols() != 3) || !window.allFinite() ||
      (window.rows() > 0 && !(window.col(1).array() >= 1.0).all()) || !(variance > 0.0) ||
      !std::isfinite(variance))
    throw InputError("adaptive noise: the saved window is not (squared norm, entries, trace) rows");
  steps_.clear();
  for (Eigen::Index i = std::max<Eigen::Index>(0, window.rows() - window_); i < window.rows(); ++i)
    steps_.push_back({window(i, 0), window(i, 1), window(i, 2)});
  variance_ = variance;
  if (window.rows() > window_) update();
}

}  // namespace bcassim
