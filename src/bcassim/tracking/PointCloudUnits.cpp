#include "bcassim/tracking/PointCloudUnits.h"

#include <fmt/format.h>

#include "bcassim/Error.h"

namespace bcassim {

double boundingBoxDiagonal(const Eigen::MatrixX3d& P) {
  if (P.rows() < 2) return 0.0;
  return (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
}

void requireMatchingUnits(const Eigen::MatrixX3d& points, const TriMesh& surface) {
  // A factor of 30 is ~sqrt(1000): halfway, on a log scale, between equal units and a factor
  // 1000, with room for views covering a tenth of the surface.
  constexpr double kMaxRatio = 30.0;
  const double pointsSize = boundingBoxDiagonal(points);
  const double surfaceSize = boundingBoxDiagonal(surface.V);
  if (!(pointsSize > 0.0) || !(surfaceSize > 0.0))
    throw InputError(
        fmt::format("point cloud bounding-box diagonal {:.4g}, surface's {:.4g}; "
                    "expected both to have an extent",
                    pointsSize, surfaceSize));
  const double ratio = pointsSize / surfaceSize;
  if (ratio <= kMaxRatio && ratio >= 1.0 / kMaxRatio) return;
  throw InputError(fmt::format(
      "point cloud bounding-box diagonal {:.4g} but the surface's is {:.4g} (ratio {:.4g}): the "
      "points look like {} for a surface in {}; expected both in metres",
      pointsSize, surfaceSize, ratio, ratio > 1.0 ? "millimetres" : "metres",
      ratio > 1.0 ? "metres" : "millimetres"));
}

}  // namespace bcassim
