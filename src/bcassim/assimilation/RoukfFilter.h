// Reduced-order unscented Kalman filter (thesis Alg. 2, eq. 3.9-3.12; Moireau & Chapelle 2011):
// the covariance is kept factored as P = L U^-1 L^T of rank r, so a step forecasts r+1 simplex
// points however large the physical part of the state is.
#pragma once
#include <vector>

#include "bcassim/assimilation/CovarianceRepair.h"
#include "bcassim/assimilation/Filter.h"
#include "bcassim/assimilation/FilterOptions.h"
#include "bcassim/assimilation/ForecastEnsemble.h"
#include "bcassim/assimilation/SigmaPointSet.h"

namespace bcassim {

struct RoukfOptions : FilterOptions {
  // The algebra needs only sum w I = 0 and sum w I I^T = Id, which every set satisfies; simplex is
  // the thesis' choice and the cheapest (r+1 forecasts).
  SigmaPointKind sigmaPoints = SigmaPointKind::Simplex;
  // Process noise on the parameters (variances in the unconstrained space, one per stochastic
  // state entry, zero on the physical part; empty = none): a random walk of the parameters, so
  // that the filter follows parameters that change from step to step. Added in the reduced
  // space, so the rank stays: with L_p the parameter rows of L after the forecast,
  // U^-1 += L_p^+ Q_p L_p^+T, which adds exactly Q_p to the parameters' covariance and moves the
  // physical part with them through the sensitivities L L_p^+ (Moireau & Chapelle 2011). With a
  // parameter-only state this is the Kalman filter's P + Q.
  Eigen::VectorXd processVariance;
  // Iterated analysis where the forecasts' linearisation is far from the analysed mean (a
  // parameter-only state: static frames). When the analysis moves the mean by more than
  // reforecastBeyond forecast standard deviations (Mahalanobis distance under the forecast
  // covariance), the models re-centre on the analysed mean (ForecastModel::recentre), the sigma
  // points are drawn about it with the analysed covariance and forecast again, and the frame is
  // analysed again from the same forecast mean and covariance with the observations linearised
  // there (the iterated posterior linearisation filter, Garcia-Fernandez et al. 2015; with a
  // small analysed spread, Gauss-Newton on the frame's posterior). Up to `reforecasts` times,
  // until one moves the mean by less than relinearizationTolerance of its analysed spread, or the
  // models say forecasts about the new mean cannot change the analysis (a linear response).
  // Not with a distribution (forecasts on other processes): InputError.
  int reforecasts = 0;
  double reforecastBeyond = 1.0;
};

// Reduced state: the r directions that carry uncertainty are every parameter plus every entry of
// the physical part whose initial standard deviation is > 0 (none, typically: positions start
// known and become uncertain only through the parameters). L (n x r) starts as the matching
// columns of the identity and U = diag(1/sigma^2). The other physical entries are still in the
// state and are corrected through the rows of L that the forecasts fill in (eq. 3.10). Process
// noise is taken on the parameters only (RoukfOptions::processVariance): on the physical part it
// would raise the rank.
class RoukfFilter final : public Filter {
 public:
  RoukfFilter(StochasticState layout, std::vector<ForecastModel*> models, Executor& executor,
              const RoukfOptions& options = {});

  FilterStepReport step(const Observation& y) override;
  const Eigen::VectorXd& mean() const override { return x_; }
  // L U^-1 L^T, n x n: for tests and small states.
  Eigen::MatrixXd covariance() const override;
  Eigen::MatrixXd covarianceFactor() const override;
  FilterState saveState() const override;
  void restoreState(const FilterState& state) override;  // L C^-T with U = C C^T, n x r

  Eigen::Index rank() const { return L_.cols(); }
  const Eigen::MatrixXd& basis() const { return L_; }             // L, n x r
  const Eigen::MatrixXd& reducedPrecision() const { return U_; }  // U, r x r

  // Replaces the estimate (restoring a checkpoint): mean (n), L (n x r), U (r x r, SPD).
  void reset(Eigen::VectorXd mean, Eigen::MatrixXd L, Eigen::MatrixXd U);

 private:
  void addParameterNoise(RepairLog& repairs);
  double predictedTrace(const Eigen::MatrixXd& HL, RepairLog& repairs) const;
  struct Linearisation;
  Eigen::VectorXd correct(const Observation& y, Observation used, Linearisation& at,
                          const Eigen::VectorXd& forecastMean, const Eigen::MatrixXd& forecastU,
                          FilterStepReport& report, RepairLog& repairs);

  ForecastEnsemble ensemble_;
  SigmaPointSet sigma_;
  Eigen::VectorXd processVariance_;  // parameters' part of RoukfOptions::processVariance
  int relinearizations_ = 0;
  int forecastRetries_ = 3;
  double relinearizationTolerance_ = 0.1;
  int reforecasts_ = 0;
  double reforecastBeyond_ = 1.0;
  Eigen::VectorXd x_;
  Eigen::MatrixXd L_;
  Eigen::MatrixXd U_;
};

}  // namespace bcassim
