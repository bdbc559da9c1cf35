#include "bcassim/mesh/VoxelGrid.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace bcassim {
namespace {

struct CellHash {
  size_t operator()(const std::array<std::int64_t, 3>& c) const {
    return static_cast<size_t>(c[0] * 73856093LL ^ c[1] * 19349663LL ^ c[2] * 83492791LL);
  }
};

}  // namespace

Eigen::MatrixX3d voxelGridCentroids(const Eigen::MatrixX3d& P, double voxel) {
  if (!(voxel > 0) || !std::isfinite(voxel))
    throw std::invalid_argument("voxelGridCentroids: the voxel edge must be positive");
  std::unordered_map<std::array<std::int64_t, 3>, int, CellHash> cells;
  cells.reserve(static_cast<size_t>(P.rows()));
  std::vector<Eigen::Vector3d> sums;
  std::vector<int> counts;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    std::array<std::int64_t, 3> key;
    for (int k = 0; k < 3; ++k) {
      // Clamped so that the cast is defined: a cell index must fit (NaN goes to the lowest).
      double q = std::floor(P(i, k) / voxel);
      if (!(q > -4e18)) q = -4e18;
      if (!(q < 4e18)) q = 4e18;
      key[k] = static_cast<std::int64_t>(q);
    }
    const auto [it, inserted] = cells.emplace(key, static_cast<int>(sums.size()));
    if (inserted) {
      sums.emplace_back(Eigen::Vector3d::Zero());
      counts.push_back(0);
    }
    sums[static_cast<size_t>(it->second)] += P.row(i).transpose();
    ++counts[static_cast<size_t>(it->second)];
  }
  Eigen::MatrixX3d out(static_cast<Eigen::Index>(sums.size()), 3);
  for (size_t c = 0; c < sums.size(); ++c)
    out.row(static_cast<Eigen::Index>(c)) = (sums[c] / counts[c]).transpose();
  return out;
}

ThinnedPoints thinToAtMost(const Eigen::MatrixX3d& P, int maxPoints, double voxel) {
  if (maxPoints < 8) throw std::invalid_argument("thinToAtMost: maxPoints must be at least 8");
  ThinnedPoints out;
  if (voxel > 0) {
    out.points = voxelGridCentroids(P, voxel);
    out.voxel = voxel;
  } else {
    out.points = P;
  }
  if (out.points.rows() <= maxPoints) return out;
  const double diagonal = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
  double edge = voxel > 0 ? 1.25 * voxel : diagonal / std::sqrt(static_cast<double>(maxPoints)) / 2;
  if (!(edge > 0) || !std::isfinite(edge)) edge = 1.0;  // all points at one place
  // A cube wider than the whole set leaves at most 8 cells: the loop ends by then.
  for (;; edge *= 1.25) {
    out.points = voxelGridCentroids(P, edge);
    out.voxel = edge;
    if (out.points.rows() <= maxPoints) return out;
  }
}

}  // namespace bcassim
