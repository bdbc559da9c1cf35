// Where a filter's large dense kernels run: the Gram matrix of its forecasts' deviations and the
// Cholesky factor of its covariance (a full-state UKF's thousands of rows). This class runs them
// here, on the system BLAS/LAPACK; distributed/ shares them with the processes that forecast.
#pragma once
#include <Eigen/Core>

namespace bcassim {

class DenseAlgebra {
 public:
  virtual ~DenseAlgebra() = default;

  // P = sum_i w_i d_i d_i^T (symmetric) over the columns d_i of `deviations`, which are
  // scale * (f_i - mean) for the step's forecasts f_i, every column present here; w >= 0. A
  // process holding some of the forecasts itself may form their deviations from them with
  // `scale` (about a point of its own) instead of reading `deviations`.
  virtual void weightedGram(const Eigen::MatrixXd& deviations, const Eigen::VectorXd& w,
                            double scale, Eigen::MatrixXd& P);

  // The lower Cholesky factor L of the symmetric A (L L^T = A, upper triangle zero); false if A
  // is not (numerically) positive definite.
  virtual bool choleskyLower(const Eigen::MatrixXd& A, Eigen::MatrixXd& L);
};

}  // namespace bcassim
