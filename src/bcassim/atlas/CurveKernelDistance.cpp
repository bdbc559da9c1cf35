#include "bcassim/atlas/CurveKernelDistance.h"

#include <fmt/format.h>

#include <cmath>
#include <numeric>

#include "bcassim/Error.h"
#include "bcassim/atlas/FaceKernelSum.h"

namespace bcassim {

OrientedFaces orientedSegments(const Eigen::MatrixX3d& V, const Eigen::MatrixX2i& E) {
  if (E.size() > 0 && (E.minCoeff() < 0 || E.maxCoeff() >= V.rows())) {
    throw InputError(fmt::format("curve edge vertex index out of range [0, {})", V.rows()));
  }
  const auto ne = static_cast<size_t>(E.rows());
  OrientedFaces o;
  for (auto* v : {&o.cx, &o.cy, &o.cz, &o.nx, &o.ny, &o.nz, &o.invNorm}) v->resize(ne);
  // A curve's edges come in walking order, near ones together: tiles stay small without sorting.
  o.face.resize(ne);
  std::iota(o.face.begin(), o.face.end(), 0);
  for (size_t e = 0; e < ne; ++e) {
    const auto i = static_cast<Eigen::Index>(e);
    const Eigen::Vector3d a = V.row(E(i, 0)), b = V.row(E(i, 1));
    const Eigen::Vector3d c = 0.5 * (a + b), n = b - a;
    const double norm = n.norm();
    o.cx[e] = c.x();
    o.cy[e] = c.y();
    o.cz[e] = c.z();
    o.nx[e] = n.x();
    o.ny[e] = n.y();
    o.nz[e] = n.z();
    o.invNorm[e] = norm > 0.0 ? 1.0 / norm : 0.0;
  }
  return o;
}

CurveKernelDistance::CurveKernelDistance(const Eigen::MatrixX3d& targetV,
                                         const Eigen::MatrixX2i& targetEdges,
                                         Eigen::MatrixX2i sourceEdges, double sigmaW)
    : target_(orientedSegments(targetV, targetEdges)),
      source_(std::move(sourceEdges)),
      sigma_(sigmaW) {
  if (!(sigmaW > 0.0) || !std::isfinite(sigmaW)) {
    throw InputError(fmt::format("data-term kernel width must be positive, got {}", sigmaW));
  }
  if (targetEdges.rows() == 0 || source_.rows() == 0) {
    throw InputError("curve data term: the source or the target curve has no edges");
  }
  targetNorm2_ = faceKernelSum(target_, target_, sigma_, FaceKernelKind::Varifold);
}

double CurveKernelDistance::value(const Eigen::MatrixX3d& V) const {
  const OrientedFaces s = orientedSegments(V, source_);
  return faceKernelSum(s, s, sigma_, FaceKernelKind::Varifold) + targetNorm2_ -
         2.0 * faceKernelSum(s, target_, sigma_, FaceKernelKind::Varifold);
}

double CurveKernelDistance::addValueAndGradient(const Eigen::MatrixX3d& V,
                                                Eigen::MatrixX3d* grad) const {
  const OrientedFaces s = orientedSegments(V, source_);
  Eigen::MatrixX3d gcSS, gnSS, gcST, gnST;
  const double ss = faceKernelSum(s, s, sigma_, FaceKernelKind::Varifold, &gcSS, &gnSS);
  const double st = faceKernelSum(s, target_, sigma_, FaceKernelKind::Varifold, &gcST, &gnST);
  // The kernel is symmetric, so d<S,S>/d(c_i, n_i) is twice the one-sided derivative; then
  // c = (a + b) / 2 and n = b - a.
  const Eigen::MatrixX3d gc = 2.0 * (gcSS - gcST), gn = 2.0 * (gnSS - gnST);
  for (Eigen::Index e = 0; e < source_.rows(); ++e) {
    grad->row(source_(e, 0)) += 0.5 * gc.row(e) - gn.row(e);
    grad->row(source_(e, 1)) += 0.5 * gc.row(e) + gn.row(e);
  }
  return ss + targetNorm2_ - 2.0 * st;
}

}  // namespace bcassim
