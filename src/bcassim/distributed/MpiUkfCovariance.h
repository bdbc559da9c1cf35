// Rank 0's side of a full-state UKF covariance kept over the ranks of the MPI executor: each
// UkfCovariance call tells the workers the matching command (MpiForecastProtocol.h) and joins
// them in the same UkfCovarianceShare method. Every rank forms and forecasts its own block of
// sigma points from the factor's columns it is handed; rank 0 receives only the observables.
#pragma once
#include "bcassim/assimilation/UkfCovariance.h"
#include "bcassim/distributed/MpiForecastDistribution.h"
#include "bcassim/distributed/UkfCovarianceShare.h"

namespace bcassim {

class MpiUkfCovariance final : public UkfCovariance {
 public:
  // Collective with the workers' kUkfSetUp: hands them `sigma` (a structured set).
  MpiUkfCovariance(MpiForecastDistribution& distribution, const SigmaPointSet& sigma);

  void assign(const Eigen::MatrixXd& P) override;
  Eigen::MatrixXd matrix() override;
  Eigen::VectorXd diagonal() override;
  void addToDiagonal(const Eigen::VectorXd& q) override;
  void forecast(ForecastEnsemble& ensemble, const SigmaPointSet& sigma, const Eigen::VectorXd& x,
                double spread, Eigen::MatrixXd& observables, RepairLog& repairs) override;
  void moments(const SigmaPointSet& sigma, double spread, Eigen::VectorXd& x) override;
  Eigen::MatrixXd correct(const Eigen::MatrixXd& weightedDz, const Eigen::MatrixXd& C) override;
  void keep() override;
  void restore() override;

 private:
  static SigmaPointColumns announce(MpiForecastDistribution& distribution,
                                    const SigmaPointSet& sigma);

  MpiForecastDistribution& distribution_;
  int n_;
  int draws_ = 0;  // forecast() calls so far
  UkfCovarianceShare share_;
};

}  // namespace bcassim
