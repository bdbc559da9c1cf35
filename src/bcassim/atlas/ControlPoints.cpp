#include "bcassim/atlas/ControlPoints.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

Eigen::MatrixX3d regularGridControlPoints(const Eigen::MatrixX3d& V, double spacing) {
  if (V.rows() == 0) throw InputError("control points: the shape has no vertices");
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InputError(fmt::format("control-point spacing must be positive, got {}", spacing));
  }
  const Eigen::RowVector3d lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff();
  Eigen::Array3i n;
  Eigen::RowVector3d start;
  for (int d = 0; d < 3; ++d) {
    const double extent = hi(d) - lo(d);
    n(d) = static_cast<int>(std::floor(extent / spacing)) + 1;
    start(d) = lo(d) + 0.5 * (extent - (n(d) - 1) * spacing);
  }
  Eigen::MatrixX3d q(n.prod(), 3);
  Eigen::Index row = 0;
  for (int i = 0; i < n(0); ++i)
    for (int j = 0; j < n(1); ++j)
      for (int k = 0; k < n(2); ++k) q.row(row++) = start + spacing * Eigen::RowVector3d(i, j, k);
  return q;
}

}  // namespace bcassim
