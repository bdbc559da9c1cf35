#include "bcassim/mechanics/LoadFootprint.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

LoadFootprint::LoadFootprint(const Eigen::MatrixX3d& rest, std::vector<double> base)
    : base_(std::move(base)) {
  const Eigen::Index n = rest.rows();
  if (n < 3)
    throw InputError(
        fmt::format("load footprint: the load has {} node{}; a footprint needs at least 3", n,
                    n == 1 ? "" : "s"));
  if (base_.empty()) base_.assign(static_cast<size_t>(n), 1.0 / static_cast<double>(n));
  if (static_cast<Eigen::Index>(base_.size()) != n)
    throw InputError("load footprint: one base share per node expected");
  double total = 0.0;
  for (double b : base_) total += b;
  for (double& b : base_) b /= total;
  const Eigen::Map<const Eigen::VectorXd> w(base_.data(), n);
  centre_ = (rest.transpose() * w);
  const Eigen::MatrixX3d d = rest.rowwise() - centre_.transpose();
  const Eigen::Matrix3d covariance = d.transpose() * w.asDiagonal() * d;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance);
  // Eigenvalues ascending: the two largest span the zone's plane.
  const double inPlane = eig.eigenvalues()(1) + eig.eigenvalues()(2);
  if (!(inPlane > 0.0))
    throw InputError("load footprint: the load's nodes coincide; a footprint needs a zone");
  radius_ = std::sqrt(inPlane);
  uv_.resize(n, 2);
  uv_.col(0) = d * eig.eigenvectors().col(2) / radius_;
  uv_.col(1) = d * eig.eigenvectors().col(1) / radius_;
}

std::vector<double> LoadFootprint::shares() const {
  const Eigen::Index n = uv_.rows();
  Eigen::ArrayXd exponent = coefficients_(0) * uv_.col(0).array() +
                            coefficients_(1) * uv_.col(1).array() -
                            0.5 * coefficients_(2) * uv_.rowwise().squaredNorm().array();
  exponent -= exponent.maxCoeff();  // no overflow whatever the coefficients
  std::vector<double> s(static_cast<size_t>(n));
  double total = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    s[static_cast<size_t>(k)] = base_[static_cast<size_t>(k)] * std::exp(exponent(k));
    total += s[static_cast<size_t>(k)];
  }
  for (double& v : s) v /= total;
  return s;
}

}  // namespace bcassim
