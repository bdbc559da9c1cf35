#include "bcassim/coupling/PointCloudObservation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "bcassim/Error.h"
#include "bcassim/mesh/ClosestPoint.h"

namespace bcassim {

PointCloudObservation::PointCloudObservation(Eigen::MatrixX3i surface, Eigen::Index nodes,
                                             const PointCloudSettings& settings)
    : surface_(std::move(surface)),
      nodes_(nodes),
      residual_(settings.residual),
      distanceFactor_(settings.distanceFactor),
      minCutoff_(settings.minCutoff),
      maxCutoff_(settings.maxCutoff),
      keepFraction_(settings.keepFraction),
      minPoints_(settings.minPoints) {
  if (surface_.rows() == 0) throw InputError("point cloud: the observed surface has no triangle");
  if (surface_.minCoeff() < 0 || surface_.maxCoeff() >= nodes_)
    throw InputError(
        fmt::format("point cloud: an observed triangle names node {}; the mesh has {} nodes",
                    surface_.minCoeff() < 0 ? surface_.minCoeff() : surface_.maxCoeff(), nodes_));
}

Vec3 PointCloudObservation::pointOn(int i, const Eigen::VectorXd& positions) const {
  const auto f = static_cast<Eigen::Index>(face_[static_cast<size_t>(i)]);
  const Vec3& w = weights_[static_cast<size_t>(i)];
  return w(0) * positions.segment<3>(3 * surface_(f, 0)) +
         w(1) * positions.segment<3>(3 * surface_(f, 1)) +
         w(2) * positions.segment<3>(3 * surface_(f, 2));
}

Observation PointCloudObservation::linearize(const Eigen::VectorXd& meanObservable,
                                             const Observation& frame) {
  if (meanObservable.size() != 3 * nodes_)
    throw std::logic_error("point cloud: the observables are not the positions of the nodes");
  if (frame.values.size() % 3 != 0 || frame.variance.size() != frame.values.size())
    throw InputError(
        fmt::format("point cloud frame of {} values and {} variances; expected 3 of each per point",
                    frame.values.size(), frame.variance.size()));
  const int n = static_cast<int>(frame.values.size() / 3);
  const auto present = [&](int i) {
    return frame.present.empty() || frame.present[3 * static_cast<size_t>(i)];
  };

  // The mean's surface, searched once per point (the triangles keep the mesh's node ids).
  TriMesh mean;
  mean.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      meanObservable.data(), nodes_, 3);
  mean.F = surface_;
  if (locator_) {
    locator_->refit(mean);
  } else {
    locator_.emplace(mean);
  }
  const SurfaceLocator& locator = *locator_;
  face_.assign(static_cast<size_t>(n), 0);
  weights_.assign(static_cast<size_t>(n), Vec3(1, 0, 0));
  normal_.assign(static_cast<size_t>(n), Vec3::UnitX());
  std::vector<double> distance(static_cast<size_t>(n), 0.0), seen;
  for (int i = 0; i < n; ++i) {
    if (!present(i)) continue;
    const SurfacePoint c = locator.closest(frame.values.segment<3>(3 * i));
    const auto k = static_cast<size_t>(i);
    face_[k] = c.face;
    weights_[k] = c.barycentric;
    const Vec3 a = mean.V.row(surface_(c.face, 0)), b = mean.V.row(surface_(c.face, 1)),
               d = mean.V.row(surface_(c.face, 2));
    const Vec3 normal = (b - a).cross(d - a);
    normal_[k] = normal.norm() > 0 ? Vec3(normal.normalized()) : Vec3(Vec3::UnitX());
    distance[k] = c.distance;
    seen.push_back(c.distance);
  }

  // Robust cutoff: k times the median distance of the closest keep_fraction of the points, never
  // below the floor nor above the ceiling, nor beyond the last of those points (when some are
  // left out).
  stats_ = {};
  stats_.points = static_cast<int>(seen.size());
  double lastKept = std::numeric_limits<double>::infinity();
  if (!seen.empty()) {
    const auto kept = std::max<size_t>(
        1, static_cast<size_t>(std::ceil(keepFraction_ * static_cast<double>(seen.size()) - 1e-9)));
    if (kept < seen.size()) {  // with every point kept, the median below is all there is to find
      std::nth_element(seen.begin(), seen.begin() + static_cast<long>(kept - 1), seen.end());
      lastKept = seen[kept - 1];
    }
    std::nth_element(seen.begin(), seen.begin() + static_cast<long>(kept / 2),
                     seen.begin() + static_cast<long>(kept));
    stats_.medianDistance = seen[kept / 2];
  }
  stats_.cutoff = std::min(
      {std::max(distanceFactor_ * stats_.medianDistance, minCutoff_), maxCutoff_, lastKept});
  std::vector<bool> used(static_cast<size_t>(n), false);
  for (int i = 0; i < n; ++i) {
    used[static_cast<size_t>(i)] = present(i) && distance[static_cast<size_t>(i)] <= stats_.cutoff;
    stats_.used += used[static_cast<size_t>(i)] ? 1 : 0;
  }
  if (stats_.used < minPoints_) {
    std::fill(used.begin(), used.end(), false);
    stats_.used = 0;
  }

  Observation out;
  if (residual_ == CloudResidual::Point) {
    out.values = frame.values;
    out.variance = frame.variance;
    out.present.assign(3 * static_cast<size_t>(n), false);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c)
        out.present[3 * static_cast<size_t>(i) + static_cast<size_t>(c)] =
            used[static_cast<size_t>(i)] &&
            (frame.present.empty() ||
             frame.present[3 * static_cast<size_t>(i) + static_cast<size_t>(c)]);
    return out;
  }
  out.values.resize(n);
  out.variance.resize(n);
  out.present = used;
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<size_t>(i);
    out.values(i) = used[k] ? normal_[k].dot(frame.values.segment<3>(3 * i)) : 0.0;
    out.variance(i) = frame.variance(3 * i);
  }
  return out;
}

void PointCloudObservation::predict(const Eigen::VectorXd& observable,
                                    Eigen::VectorXd& predicted) const {
  const auto n = static_cast<int>(face_.size());
  predicted.resize(residual_ == CloudResidual::Point ? 3 * n : n);
  for (int i = 0; i < n; ++i) {
    const Vec3 p = pointOn(i, observable);
    if (residual_ == CloudResidual::Point)
      predicted.segment<3>(3 * i) = p;
    else
      predicted(i) = normal_[static_cast<size_t>(i)].dot(p);
  }
}

Eigen::MatrixX3d PointCloudObservation::surfacePositions(const Eigen::VectorXd& positions) const {
  const std::set<int> nodes(surface_.data(), surface_.data() + surface_.size());
  Eigen::MatrixX3d P(static_cast<Eigen::Index>(nodes.size()), 3);
  Eigen::Index row = 0;
  for (int node : nodes) P.row(row++) = positions.segment<3>(3 * node).transpose();
  return P;
}

}  // namespace bcassim
