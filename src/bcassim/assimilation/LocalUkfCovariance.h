// A UKF's covariance as one dense n x n matrix in this process, its kernels on the system
// BLAS/LAPACK: the filter alone, or on threads.
#pragma once
#include "bcassim/assimilation/UkfCovariance.h"

namespace bcassim {

class LocalUkfCovariance final : public UkfCovariance {
 public:
  void assign(const Eigen::MatrixXd& P) override { P_ = P; }
  Eigen::MatrixXd matrix() override { return P_; }
  Eigen::VectorXd diagonal() override { return P_.diagonal(); }
  void addToDiagonal(const Eigen::VectorXd& q) override { P_.diagonal() += q; }
  void forecast(ForecastEnsemble& ensemble, const SigmaPointSet& sigma, const Eigen::VectorXd& x,
                double spread, Eigen::MatrixXd& observables, RepairLog& repairs) override;
  void moments(const SigmaPointSet& sigma, double spread, Eigen::VectorXd& x) override;
  Eigen::MatrixXd correct(const Eigen::MatrixXd& weightedDz, const Eigen::MatrixXd& C) override;
  void keep() override { kept_ = P_; }
  void restore() override { P_ = kept_; }

 private:
  Eigen::MatrixXd P_, kept_;
  Eigen::MatrixXd forecasts_, deviations_;  // this step's, (f_k - x) / spread
};

}  // namespace bcassim
