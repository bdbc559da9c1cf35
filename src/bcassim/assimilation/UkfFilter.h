// Unscented Kalman filter on the full stochastic state (thesis Alg. 1, eq. 3.3 and 3.8) with star,
// canonical or simplex sigma points.
#pragma once
#include <memory>
#include <vector>

#include "bcassim/assimilation/Filter.h"
#include "bcassim/assimilation/FilterOptions.h"
#include "bcassim/assimilation/ForecastEnsemble.h"
#include "bcassim/assimilation/SigmaPointSet.h"
#include "bcassim/assimilation/UkfCovariance.h"

namespace bcassim {

struct UkfOptions : FilterOptions {
  SigmaPointKind sigmaPoints = SigmaPointKind::Star;
  double starKappa = 0.0;  // see starSigmaPoints()
  // Spread alpha of a scaled unscented transform: the sigma points sit at alpha times their usual
  // distance from the mean, and the deviations of the forecasts from their mean are divided by
  // alpha before the covariances are formed (exact for a linear model whatever alpha). In n
  // dimensions the usual sets put points sqrt(n) standard deviations out; 1/sqrt(n) brings them
  // back to one. 1 = the plain transform (thesis Alg. 1).
  double spread = 1.0;
  // Diagonal process noise Q (unconstrained variances, one per stochastic state entry) added to the
  // predicted covariance (Alg. 1 line 14); empty = none. The correction does not see it in the
  // predicted observations, as in the thesis: on parameters that is exact for a linear model.
  // With a parameter-only state (static frames, whose observations depend on the parameters
  // directly) Q is added before the sigma points are drawn: the Kalman filter's P + Q, F = Id.
  Eigen::VectorXd processVariance;
};

class UkfFilter final : public Filter {
 public:
  // Starts from the layout's initial mean and diagonal covariance. Throws InputError on sizes.
  UkfFilter(StochasticState layout, std::vector<ForecastModel*> models, Executor& executor,
            UkfOptions options = {});

  FilterStepReport step(const Observation& y) override;
  const Eigen::VectorXd& mean() const override { return x_; }
  Eigen::MatrixXd covariance() const override { return P_->matrix(); }
  Eigen::MatrixXd covarianceFactor() const override;
  FilterState saveState() const override;
  void restoreState(const FilterState& state) override;  // Cholesky factor of P, n x n

  // Replaces the estimate (restoring a checkpoint, or a prior with correlations). A covariance that
  // is not positive definite is repaired at the next step and reported there.
  void reset(Eigen::VectorXd mean, const Eigen::MatrixXd& covariance);

 private:
  ForecastEnsemble ensemble_;
  UkfOptions options_;
  SigmaPointSet sigma_;
  Eigen::VectorXd x_;
  // Here, or shared with the distribution's processes. Its methods gather from them: logically
  // const.
  std::unique_ptr<UkfCovariance> P_;
};

}  // namespace bcassim
