// Where a UKF keeps its state covariance between steps, and the parts of a step that touch it:
// one dense n x n matrix in this process (LocalUkfCovariance), or pieces spread over the
// processes that forecast (distributed/), so that no process holds or passes over all of it.
#pragma once
#include <Eigen/Core>

#include "bcassim/assimilation/CovarianceRepair.h"
#include "bcassim/assimilation/SigmaPointSet.h"

namespace bcassim {

class ForecastEnsemble;

class UkfCovariance {
 public:
  virtual ~UkfCovariance() = default;

  // P = `P` (n x n, symmetric).
  virtual void assign(const Eigen::MatrixXd& P) = 0;
  // The whole P (gathered: for checkpoints and reports, not per step).
  virtual Eigen::MatrixXd matrix() = 0;
  virtual Eigen::VectorXd diagonal() = 0;
  // P += diag(q).
  virtual void addToDiagonal(const Eigen::VectorXd& q) = 0;

  // The prediction's first half: the sigma points x + spread C I^(k) of `sigma` (C C^T = P, its
  // repairs into `repairs`) forecast through `ensemble`; writes the observables of every point
  // (observableSize x s). Throws what the forecasts or the factorisation throw.
  virtual void forecast(ForecastEnsemble& ensemble, const SigmaPointSet& sigma,
                        const Eigen::VectorXd& x, double spread, Eigen::MatrixXd& observables,
                        RepairLog& repairs) = 0;
  // Its second half, after forecast(): the forecasts' weighted mean into `x` and P = sum_k w_k
  // d_k d_k^T with d_k = (f_k - x) / spread.
  virtual void moments(const SigmaPointSet& sigma, double spread, Eigen::VectorXd& x) = 0;
  // The correction after moments(): with weightedDz (s x m) the rows w_k (z_k - z) / spread of
  // the predicted observations' deviations and C the lower Cholesky factor of their covariance
  // Pz, returns G = C^-1 Pxz^T (m x n; Pxz = sum_k w_k d_k (z_k - z)^T / spread) and applies
  // P -= G^T G.
  virtual Eigen::MatrixXd correct(const Eigen::MatrixXd& weightedDz, const Eigen::MatrixXd& C) = 0;

  // Keeps P as it is now / puts it back (a relinearisation corrects from the same forecast).
  virtual void keep() = 0;
  virtual void restore() = 0;
};

}  // namespace bcassim
