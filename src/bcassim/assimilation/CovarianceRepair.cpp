#include "bcassim/assimilation/CovarianceRepair.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

Eigen::MatrixXd choleskyWithRepair(const Eigen::MatrixXd& P, RepairLog& log) {
  if (!P.allFinite()) throw NumericalError("covariance has non-finite entries");
  Eigen::LLT<Eigen::MatrixXd> llt(P);
  if (llt.info() == Eigen::Success) return llt.matrixL();

  const Eigen::Index n = P.rows();
  const Eigen::MatrixXd S = 0.5 * (P + P.transpose());
  // Scale the jitter to the matrix so that repairs are relative, whatever the units.
  const double scale = n > 0 ? std::max(S.diagonal().cwiseAbs().mean(), 1e-300) : 1.0;
  for (double jitter = 1e-10 * scale; jitter <= 1e10 * scale; jitter *= 10) {
    llt.compute(S + jitter * Eigen::MatrixXd::Identity(n, n));
    if (llt.info() == Eigen::Success) {
      ++log.repairs;
      log.largestJitter = std::max(log.largestJitter, jitter);
      return llt.matrixL();
    }
  }
  throw NumericalError("covariance is not positive definite and jitter did not repair it");
}

}  // namespace bcassim
