#include "bcassim/atlas/SurfaceAttachment.h"

#include <fmt/format.h>

#include <utility>

#include "bcassim/Error.h"
#include "bcassim/mesh/ClosestPoint.h"

namespace bcassim {

SurfaceAttachment::SurfaceAttachment(const TriMesh& surface, const Eigen::MatrixX3d& points)
    : corners_(points.rows(), 3), weights_(points.rows(), 3), distance_(points.rows()) {
  const SurfaceLocator locator(surface);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const SurfacePoint sp = locator.closest(points.row(i).transpose());
    corners_.row(i) = surface.F.row(sp.face);
    weights_.row(i) = sp.barycentric.transpose();
    distance_(i) = sp.distance;
  }
}

SurfaceAttachment::SurfaceAttachment(Eigen::MatrixX3i corners, Eigen::MatrixX3d weights)
    : corners_(std::move(corners)),
      weights_(std::move(weights)),
      distance_(Eigen::VectorXd::Zero(corners_.rows())) {
  if (corners_.rows() != weights_.rows()) {
    throw InputError(fmt::format("surface attachment: {} corner rows but {} weight rows",
                                 corners_.rows(), weights_.rows()));
  }
  if (corners_.size() > 0 && corners_.minCoeff() < 0) {
    throw InputError("surface attachment: negative vertex index");
  }
}

Eigen::MatrixX3d SurfaceAttachment::positions(const Eigen::MatrixX3d& V) const {
  if (corners_.size() > 0 && corners_.maxCoeff() >= V.rows()) {
    throw InputError(fmt::format("surface attachment: {} vertices, the attached faces need {}",
                                 V.rows(), corners_.maxCoeff() + 1));
  }
  Eigen::MatrixX3d p(corners_.rows(), 3);
  for (Eigen::Index i = 0; i < corners_.rows(); ++i) {
    p.row(i) = weights_(i, 0) * V.row(corners_(i, 0)) + weights_(i, 1) * V.row(corners_(i, 1)) +
               weights_(i, 2) * V.row(corners_(i, 2));
  }
  return p;
}

}  // namespace bcassim
