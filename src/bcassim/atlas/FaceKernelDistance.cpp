#include "bcassim/atlas/FaceKernelDistance.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

FaceKernelDistance::FaceKernelDistance(const TriMesh& target, double sigmaW, FaceKernelKind kind)
    : target_(orientedFaces(target.V, target.F)), sigma_(sigmaW), kind_(kind) {
  if (!(sigmaW > 0.0) || !std::isfinite(sigmaW)) {
    throw InputError(fmt::format("data-term kernel width must be positive, got {}", sigmaW));
  }
  targetNorm2_ = faceKernelSum(target_, target_, sigma_, kind_);
}

double FaceKernelDistance::value(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) const {
  const OrientedFaces s = orientedFaces(V, F);
  return faceKernelSum(s, s, sigma_, kind_) + targetNorm2_ -
         2.0 * faceKernelSum(s, target_, sigma_, kind_);
}

double FaceKernelDistance::valueAndGradient(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                            Eigen::MatrixX3d* grad) const {
  const OrientedFaces s = orientedFaces(V, F);
  Eigen::MatrixX3d gcSS, gnSS, gcST, gnST;
  const double ss = faceKernelSum(s, s, sigma_, kind_, &gcSS, &gnSS);
  const double st = faceKernelSum(s, target_, sigma_, kind_, &gcST, &gnST);
  // The kernel is symmetric, so d<S,S>/d(c_i, n_i) is twice the one-sided derivative.
  grad->setZero(V.rows(), 3);
  addFaceGradientToVertices(V, F, s, 2.0 * (gcSS - gcST), 2.0 * (gnSS - gnST), grad);
  return ss + targetNorm2_ - 2.0 * st;
}

}  // namespace bcassim
