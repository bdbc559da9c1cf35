#include "bcassim/atlas/MultiObjectDistance.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

MultiObjectDistance::MultiObjectDistance(const TriMesh& target, const Eigen::MatrixX2i& targetCurve,
                                         const Eigen::MatrixX2i& sourceCurve, double sigmaW,
                                         FaceKernelKind kind, double curveWeight)
    : surface_(target, sigmaW, kind), curve_(target.V, targetCurve, sourceCurve, sigmaW) {
  if (!(curveWeight >= 0.0) || !std::isfinite(curveWeight)) {
    throw InputError(fmt::format("curve data-term weight must be >= 0, got {}", curveWeight));
  }
  weight_ = curveWeight * surface_.targetSquaredNorm() / curve_.targetSquaredNorm();
}

double MultiObjectDistance::value(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) const {
  return surface_.value(V, F) + weight_ * curve_.value(V);
}

double MultiObjectDistance::valueAndGradient(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                             Eigen::MatrixX3d* grad) const {
  const double s = surface_.valueAndGradient(V, F, grad);
  Eigen::MatrixX3d g = Eigen::MatrixX3d::Zero(V.rows(), 3);
  const double c = curve_.addValueAndGradient(V, &g);
  *grad += weight_ * g;
  return s + weight_ * c;
}

std::unique_ptr<SurfaceDistance> makeDataTerm(const TriMesh& target, const RegistrationOptions& o,
                                              const CurvePair* curves) {
  if (!(o.curveWeight >= 0.0) || !std::isfinite(o.curveWeight)) {
    throw InputError(fmt::format("curve data-term weight must be >= 0, got {}", o.curveWeight));
  }
  if (curves && curves->present() && o.curveWeight > 0.0) {
    return std::make_unique<MultiObjectDistance>(target, curves->target, curves->source, o.sigmaW,
                                                 o.dataTerm, o.curveWeight);
  }
  return std::make_unique<FaceKernelDistance>(target, o.sigmaW, o.dataTerm);
}

}  // namespace bcassim
