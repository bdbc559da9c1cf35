// Adaptive observation noise: a common variance sigma^2 of the observed entries estimated from a
// filter's innovations by covariance matching, E[nu^T nu] = tr(H P H^T) + m sigma^2, over a window.
#pragma once
#include <Eigen/Core>
#include <deque>

namespace bcassim {

// Each observed step k brings nu_k^T nu_k (the innovation y - H x over its m_k present entries)
// and t_k = tr(H P H^T) over them (the predicted observations' spread, without R), both from
// FilterStepReport. The estimate over the last `window` observed steps is the sigma^2 that
// maximises the Gaussian likelihood of those innovations with covariance (t_k / m_k + sigma^2) I:
//   sum_k m_k (s_k - sigma^2) / (t_k / m_k + sigma^2)^2 = 0,  s_k = (nu_k^T nu_k - t_k) / m_k,
// each step's unbiased estimate s_k weighted by the inverse of its variance, so that steps whose
// prediction is wide (the first ones) count little; where t_k << sigma^2 it is the plain
// sum_k (nu_k^T nu_k - t_k) / sum_k m_k. Exact for a linear Gaussian model: E[s_k] = sigma^2 when
// the filter's P is its true error covariance. Until the window is full, the steps it lacks count
// as steps of the mean m_k that saw exactly the initial sigma^2 (s = sigma_0^2, t = 0), so the
// estimate moves from the initial sigma to the data's as the window fills. Never below floor^2.
// Steps without observations (m_k = 0) are skipped.
class InnovationNoiseEstimator {
 public:
  // window >= 1 observed steps; 0 < floor <= initialSigma (m, or the observations' unit). Throws
  // InputError otherwise.
  InnovationNoiseEstimator(double initialSigma, int window, double floor);

  // One filter step; entries = 0 (a prediction only) is skipped.
  void add(double innovationSquaredNorm, Eigen::Index entries, double predictedObservationTrace);

  // The current estimate: the noise to assume for the next step.
  double variance() const { return variance_; }
  double sigma() const;
  // Observed steps in the window (<= window).
  int steps() const { return static_cast<int>(steps_.size()); }

  // For checkpoints: the window, one row per step (innovation squared norm, entries, trace),
  // oldest first, and the estimate. restore(saved(), variance()) on an estimator of the same
  // window continues exactly; a longer saved window keeps its newest rows. Throws InputError when
  // the matrix does not have 3 columns of finite values with entries >= 1, or variance <= 0.
  Eigen::MatrixXd saved() const;
  void restore(const Eigen::MatrixXd& window, double variance);

 private:
  struct Step {
    double squaredNorm = 0.0;
    double entries = 0.0;
    double trace = 0.0;
  };
  void update();

  double initialVariance_;
  int window_;
  double floorVariance_;
  std::deque<Step> steps_;
  double variance_;
};

}  // namespace bcassim
