#include "bcassim/assimilation/CovarianceRepair.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/assimilation/LargeDenseKernels.h"

namespace bcassim {

Eigen::MatrixXd choleskyWithRepair(const Eigen::MatrixXd& P, RepairLog& log) {
  if (!P.allFinite()) throw NumericalError("covariance has non-finite entries");
  Eigen::MatrixXd L;
  // A diagonal entry <= 0 fails any Cholesky factorisation at its pivot: straight to the repair
  // (the same result, one factorisation less; a full-state UKF's fixed nodes have zero variance).
  if ((P.diagonal().array() > 0.0).all() && choleskyLower(P, L)) return L;

  const Eigen::Index n = P.rows();
  Eigen::MatrixXd S = 0.5 * (P + P.transpose());
  // Scale the jitter to the matrix so that repairs are relative, whatever the units.
  const double scale = n > 0 ? std::max(S.diagonal().cwiseAbs().mean(), 1e-300) : 1.0;
  double added = 0.0;
  for (double jitter = 1e-10 * scale; jitter <= 1e10 * scale; jitter *= 10) {
    S.diagonal().array() += jitter - added;
    added = jitter;
    if (choleskyLower(S, L)) {
      ++log.repairs;
      log.largestJitter = std::max(log.largestJitter, jitter);
      return L;
    }
  }
  throw NumericalError("covariance is not positive definite and jitter did not repair it");
}

}  // namespace bcassim
