#include "bcassim/mesh/PointSetAlignment.h"

#include <fmt/format.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

Eigen::MatrixX3d SimilarityTransform::apply(const Eigen::MatrixX3d& P) const {
  return ((scale * P) * rotation.transpose()).rowwise() + translation.transpose();
}

namespace {

void requirePairedPoints(const char* method, const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q,
                         const Eigen::VectorXd& weights) {
  if (P.rows() != Q.rows() || P.rows() < 3)
    throw InputError(
        fmt::format("{}: point sets of {} and {} rows; expected two paired sets of "
                    ">= 3 points",
                    method, P.rows(), Q.rows()));
  if (!P.allFinite() || !Q.allFinite())
    throw InputError(
        fmt::format("{}: a point has a non-finite coordinate; expected finite points", method));
  if (weights.size() == 0) return;
  if (weights.size() != P.rows())
    throw InputError(fmt::format("{}: {} weights for {} points; expected one weight per point",
                                 method, weights.size(), P.rows()));
  for (Eigen::Index i = 0; i < weights.size(); ++i)
    if (!(weights[i] >= 0.0) || !std::isfinite(weights[i]))
      throw InputError(
          fmt::format("{}: weight {} is {}; expected a finite number >= 0", method, i, weights[i]));
  if (!(weights.sum() > 0.0))
    throw InputError(fmt::format("{}: all weights are 0; expected a positive sum", method));
}

struct Fit {
  SimilarityTransform transform;
  double spreadOfP = 0.0;  // sum_i w_i |p_i - mean(P)|^2, m^2
};

// One body for both fits. Equal weights take the unweighted path so that the result is the same,
// bit for bit, as the atlas' Procrustes always gave.
Fit fit(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q, const Eigen::VectorXd& weights,
        bool withScale) {
  Eigen::RowVector3d cp, cq;
  Eigen::Matrix3d H;
  Fit result;
  if (weights.size() == 0) {
    cp = P.colwise().mean();
    cq = Q.colwise().mean();
    H = (P.rowwise() - cp).transpose() * (Q.rowwise() - cq);
    if (withScale) result.spreadOfP = (P.rowwise() - cp).squaredNorm();
  } else {
    const double total = weights.sum();
    cp = (weights.transpose() * P) / total;
    cq = (weights.transpose() * Q) / total;
    H = (P.rowwise() - cp).transpose() * weights.asDiagonal() * (Q.rowwise() - cq);
    if (withScale)
      result.spreadOfP = (weights.asDiagonal() * (P.rowwise() - cp).rowwise().squaredNorm()).sum();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // The sign fix keeps a rotation where the best orthogonal map would be a reflection.
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  SimilarityTransform& t = result.transform;
  t.rotation = svd.matrixV() * D * svd.matrixU().transpose();
  if (withScale && result.spreadOfP > 0.0) {
    // Umeyama eq. 42: s = tr(Sigma D) / spread of P.
    t.scale = svd.singularValues().dot(D.diagonal()) / result.spreadOfP;
    t.translation = cq.transpose() - t.scale * (t.rotation * cp.transpose());
  } else {
    t.translation = cq.transpose() - t.rotation * cp.transpose();
  }
  return result;
}

}  // namespace

RigidTransform kabschFit(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q,
                         const Eigen::VectorXd& weights) {
  requirePairedPoints("Kabsch", P, Q, weights);
  const SimilarityTransform t = fit(P, Q, weights, false).transform;
  RigidTransform r;
  r.rotation = t.rotation;
  r.translation = t.translation;
  return r;
}

SimilarityTransform umeyamaFit(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q,
                               const Eigen::VectorXd& weights) {
  requirePairedPoints("Umeyama", P, Q, weights);
  const Fit f = fit(P, Q, weights, true);
  if (!(f.spreadOfP > 0.0))
    throw InputError(
        "Umeyama: the weighted source points all coincide; expected points spread in "
        "space to fit a scale");
  return f.transform;
}

}  // namespace bcassim
