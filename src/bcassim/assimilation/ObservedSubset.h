// The present entries of one observation frame, validated, with a Cholesky factor of their noise
// covariance so that filters work with whitened residuals R^{-1/2}(y - z) (eq. 3.11, 3.17). A
// diagonal noise (the usual case: independent entries) is kept as its standard deviations: no
// dense R, no factorisation (a 500-point cloud's would cost more than the rest of the analysis).
#pragma once
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <vector>

#include "bcassim/assimilation/Observation.h"

namespace bcassim {

class ObservedSubset {
 public:
  // Throws InputError if sizes disagree with observationSize, a present value is not finite, or
  // the noise of the present entries is not positive definite.
  ObservedSubset(const Observation& y, Eigen::Index observationSize);

  bool empty() const { return rows_.empty(); }
  Eigen::Index size() const { return static_cast<Eigen::Index>(rows_.size()); }
  const Eigen::VectorXd& values() const { return y_; }
  // R of the present entries (dense; made on request when the noise is diagonal).
  Eigen::MatrixXd covariance() const;

  // Present rows of a predicted observation vector or of a matrix of them (one per column).
  Eigen::MatrixXd selectRows(const Eigen::MatrixXd& Z) const;
  // R^{-1/2} M with R = C C^T (M has size() rows).
  Eigen::MatrixXd whiten(const Eigen::MatrixXd& M) const;

 private:
  std::vector<Eigen::Index> rows_;
  Eigen::VectorXd y_;
  bool full_ = false;
  Eigen::VectorXd stddev_;  // diagonal noise
  Eigen::MatrixXd R_;       // full noise, with its factor
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace bcassim
