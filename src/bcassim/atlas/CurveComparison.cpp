#include "bcassim/atlas/CurveComparison.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/atlas/PlaneIntersection.h"
#include "bcassim/mesh/ClosestPoint.h"

namespace bcassim {

double distanceToPolyline(const Eigen::Vector3d& p, const Eigen::MatrixX3d& c) {
  if (c.rows() == 0) throw InputError("curve distance: empty polyline");
  double best = (p - c.row(0).transpose()).norm();
  for (Eigen::Index i = 0; i + 1 < c.rows(); ++i) {
    const Vec3 q = closestPointOnSegment(p, c.row(i).transpose(), c.row(i + 1).transpose());
    best = std::min(best, (p - q).norm());
  }
  return best;
}

CurveDistance compareCurves(const Eigen::MatrixX3d& expert, const Eigen::MatrixX3d& predicted,
                            const CuttingPlaneFamily& planes) {
  if (expert.rows() == 0 || predicted.rows() == 0) {
    throw InputError("curve distance: a curve has no points");
  }
  CurveDistance d;
  double sum = 0.0;
  for (const CuttingPlane& plane : planes.planes) {
    const auto he = intersectPolyline(expert, plane), hp = intersectPolyline(predicted, plane);
    if (he.empty() || hp.empty()) continue;
    double best = std::numeric_limits<double>::infinity();
    for (const PlaneHit& a : he)
      for (const PlaneHit& b : hp) best = std::min(best, (a.point - b.point).norm());
    ++d.planes;
    sum += best;
    d.planeMax = std::max(d.planeMax, best);
  }
  if (d.planes > 0) d.planeMean = sum / d.planes;
  double psum = 0.0;
  for (Eigen::Index i = 0; i < expert.rows(); ++i) {
    const double e = distanceToPolyline(expert.row(i).transpose(), predicted);
    psum += e;
    d.pointMax = std::max(d.pointMax, e);
  }
  d.pointMean = psum / static_cast<double>(expert.rows());
  return d;
}

CurveDistance compareCurveToBand(const Eigen::MatrixX3d& V, const Eigen::MatrixX2i& band,
                                 const Eigen::MatrixX3d& predicted,
                                 const CuttingPlaneFamily& planes) {
  if (band.rows() == 0 || predicted.rows() == 0) {
    throw InputError("curve distance: the band or the predicted curve has no points");
  }
  if (band.minCoeff() < 0 || band.maxCoeff() >= V.rows()) {
    throw InputError(
        fmt::format("curve distance: band vertex index out of range [0, {})", V.rows()));
  }
  CurveDistance d;
  double sum = 0.0;
  Eigen::MatrixX3d edge(2, 3);
  for (const CuttingPlane& plane : planes.planes) {
    const auto hp = intersectPolyline(predicted, plane);
    if (hp.empty()) continue;
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index e = 0; e < band.rows(); ++e) {
      edge.row(0) = V.row(band(e, 0));
      edge.row(1) = V.row(band(e, 1));
      for (const PlaneHit& a : intersectPolyline(edge, plane))
        for (const PlaneHit& b : hp) best = std::min(best, (a.point - b.point).norm());
    }
    if (!std::isfinite(best)) continue;
    ++d.planes;
    sum += best;
    d.planeMax = std::max(d.planeMax, best);
  }
  if (d.planes > 0) d.planeMean = sum / d.planes;
  std::vector<int> vertices(band.data(), band.data() + band.size());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  double psum = 0.0;
  for (int v : vertices) {
    const double e = distanceToPolyline(V.row(v).transpose(), predicted);
    psum += e;
    d.pointMax = std::max(d.pointMax, e);
  }
  d.pointMean = psum / static_cast<double>(vertices.size());
  return d;
}

}  // namespace bcassim
