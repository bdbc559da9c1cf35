#include "bcassim/atlas/PlaneIntersection.h"

namespace bcassim {

std::vector<PlaneHit> intersectPolyline(const Eigen::MatrixX3d& points, const CuttingPlane& plane) {
  std::vector<PlaneHit> hits;
  const Eigen::Index n = points.rows();
  auto side = [&](Eigen::Index i) {
    return (points.row(i).transpose() - plane.point).dot(plane.normal);
  };
  auto keep = [&](const Eigen::Vector3d& p, double position) {
    if (plane.radial.squaredNorm() > 0.0 && (p - plane.point).dot(plane.radial) < 0.0) return;
    hits.push_back({p, position});
  };
  for (Eigen::Index i = 0; i < n; ++i) {
    const double s0 = side(i);
    if (s0 == 0.0) {
      keep(points.row(i).transpose(), static_cast<double>(i));
      continue;
    }
    if (i + 1 >= n) break;
    const double s1 = side(i + 1);
    if ((s0 < 0.0 && s1 > 0.0) || (s0 > 0.0 && s1 < 0.0)) {
      const double t = s0 / (s0 - s1);
      keep(((1.0 - t) * points.row(i) + t * points.row(i + 1)).transpose(),
           static_cast<double>(i) + t);
    }
  }
  return hits;
}

}  // namespace bcassim
