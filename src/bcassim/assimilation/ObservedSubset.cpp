#include "bcassim/assimilation/ObservedSubset.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

ObservedSubset::ObservedSubset(const Observation& y, Eigen::Index observationSize) {
  if (y.values.size() == 0) return;
  const Eigen::Index m = observationSize;
  if (y.values.size() != m)
    throw InputError(
        fmt::format("observation frame has {} values, the model predicts {}", y.values.size(), m));
  if (!y.present.empty() && static_cast<Eigen::Index>(y.present.size()) != m)
    throw InputError(
        fmt::format("observation mask has {} entries, expected {}", y.present.size(), m));
  const bool full = y.covariance.size() > 0;
  if (full && (y.covariance.rows() != m || y.covariance.cols() != m))
    throw InputError(fmt::format("observation covariance is {}x{}, expected {}x{}",
                                 y.covariance.rows(), y.covariance.cols(), m, m));
  if (!full && y.variance.size() != m)
    throw InputError(
        fmt::format("observation frame has {} variances, expected {}", y.variance.size(), m));

  for (Eigen::Index i = 0; i < m; ++i) {
    if (!y.present.empty() && !y.present[i]) continue;
    if (!std::isfinite(y.values[i]))
      throw InputError(
          fmt::format("observation entry {} is {} but marked present", i, y.values[i]));
    if (!full && !(y.variance[i] > 0 && std::isfinite(y.variance[i])))
      throw InputError(fmt::format("observation entry {}: noise variance must be > 0, got {}", i,
                                   y.variance[i]));
    rows_.push_back(i);
  }
  const Eigen::Index n = size();
  full_ = full;
  y_.resize(n);
  for (Eigen::Index a = 0; a < n; ++a) y_[a] = y.values[rows_[a]];
  if (!full) {
    stddev_.resize(n);
    for (Eigen::Index a = 0; a < n; ++a) stddev_[a] = std::sqrt(y.variance[rows_[a]]);
    return;
  }
  R_.resize(n, n);
  for (Eigen::Index a = 0; a < n; ++a)
    for (Eigen::Index b = 0; b < n; ++b) R_(a, b) = y.covariance(rows_[a], rows_[b]);
  if (n == 0) return;
  llt_.compute(R_);
  if (llt_.info() != Eigen::Success || !R_.allFinite())
    throw InputError("observation noise covariance is not positive definite on present entries");
}

Eigen::MatrixXd ObservedSubset::covariance() const {
  if (full_) return R_;
  return stddev_.array().square().matrix().asDiagonal();
}

Eigen::MatrixXd ObservedSubset::selectRows(const Eigen::MatrixXd& Z) const {
  Eigen::MatrixXd out(size(), Z.cols());
  for (Eigen::Index a = 0; a < size(); ++a) out.row(a) = Z.row(rows_[a]);
  return out;
}

Eigen::MatrixXd ObservedSubset::whiten(const Eigen::MatrixXd& M) const {
  if (!full_) return (M.array().colwise() / stddev_.array()).matrix();  // as L's solve divides
  return llt_.matrixL().solve(M);
}

}  // namespace bcassim
