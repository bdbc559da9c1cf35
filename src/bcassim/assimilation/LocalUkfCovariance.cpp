#include "bcassim/assimilation/LocalUkfCovariance.h"

#include "bcassim/assimilation/ForecastEnsemble.h"
#include "bcassim/assimilation/LargeDenseKernels.h"

namespace bcassim {

void LocalUkfCovariance::forecast(ForecastEnsemble& ensemble, const SigmaPointSet& sigma,
                                  const Eigen::VectorXd& x, double spread,
                                  Eigen::MatrixXd& observables, RepairLog& repairs) {
  Eigen::MatrixXd factor = choleskyWithRepair(P_, repairs);
  factor *= spread;  // in place: no second n x n matrix
  const Eigen::MatrixXd X = sigma.points(x, factor);
  ensemble.forecast(X, forecasts_, observables);
}

void LocalUkfCovariance::moments(const SigmaPointSet& sigma, double spread, Eigen::VectorXd& x) {
  x = sigma.meanOf(forecasts_);
  const double unscale = 1.0 / spread;
  deviations_ = unscale * (forecasts_.colwise() - x);
  weightedGram(deviations_, sigma.weights, P_);
}

Eigen::MatrixXd LocalUkfCovariance::correct(const Eigen::MatrixXd& weightedDz,
                                            const Eigen::MatrixXd& C) {
  Eigen::MatrixXd Pxz;
  multiply(deviations_, weightedDz, Pxz);
  // With Pz = C C^T and G = C^-1 Pxz^T: K Pxz^T = G^T G, symmetric by construction.
  Eigen::MatrixXd G = C.triangularView<Eigen::Lower>().solve(Pxz.transpose());
  subtractGram(G, P_);
  return G;
}

}  // namespace bcassim
