#include "bcassim/atlas/RigidAlignment.h"

#include <fmt/format.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <limits>

#include "bcassim/Error.h"
#include "bcassim/mesh/ClosestPoint.h"

namespace bcassim {

Eigen::MatrixX3d RigidTransform::apply(const Eigen::MatrixX3d& P) const {
  return (P * rotation.transpose()).rowwise() + translation.transpose();
}

RigidTransform procrustes(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q) {
  if (P.rows() != Q.rows() || P.rows() < 3) {
    throw InputError(fmt::format("Procrustes needs two equal sets of >= 3 points, got {} and {}",
                                 P.rows(), Q.rows()));
  }
  const Eigen::RowVector3d cp = P.colwise().mean(), cq = Q.colwise().mean();
  const Eigen::Matrix3d H = (P.rowwise() - cp).transpose() * (Q.rowwise() - cq);
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // The sign fix keeps a rotation where the best orthogonal map would be a reflection.
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  RigidTransform t;
  t.rotation = svd.matrixV() * D * svd.matrixU().transpose();
  t.translation = cq.transpose() - t.rotation * cp.transpose();
  return t;
}

RigidTransform alignRigidly(const TriMesh& source, const TriMesh& target,
                            const IcpOptions& options) {
  if (source.V.rows() < 3) throw InputError("rigid alignment: source has fewer than 3 vertices");
  const SurfaceLocator locator(target);
  RigidTransform total;
  total.translation = (target.V.colwise().mean() - source.V.colwise().mean()).transpose();
  double previousRms = std::numeric_limits<double>::infinity();
  Eigen::MatrixX3d closest(source.V.rows(), 3);
  for (int it = 0; it < options.maxIterations; ++it) {
    const Eigen::MatrixX3d moved = total.apply(source.V);
    double sum2 = 0.0;
    for (Eigen::Index i = 0; i < moved.rows(); ++i) {
      const SurfacePoint sp = locator.closest(moved.row(i).transpose());
      closest.row(i) = sp.point.transpose();
      sum2 += sp.distance * sp.distance;
    }
    const double rms = std::sqrt(sum2 / static_cast<double>(moved.rows()));
    if (std::abs(previousRms - rms) < options.tolerance) break;
    previousRms = rms;
    const RigidTransform step = procrustes(moved, closest);
    total.rotation = step.rotation * total.rotation;
    total.translation = step.rotation * total.translation + step.translation;
  }
  return total;
}

}  // namespace bcassim
