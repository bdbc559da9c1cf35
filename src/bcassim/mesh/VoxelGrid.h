// Voxel-grid thinning of point sets, as PCL's VoxelGrid does it: the points in each cube of a grid
// anchored at the origin replaced by their centroid (an RGB-D frame of 10^5 points to a few
// thousand, evenly spread over what the sensor saw).
#pragma once
#include <Eigen/Core>

namespace bcassim {

// The centroid of the points of every occupied cube of edge `voxel` (same units as P, > 0), in
// the order of each cube's first point: the same result on any machine.
Eigen::MatrixX3d voxelGridCentroids(const Eigen::MatrixX3d& P, double voxel);

struct ThinnedPoints {
  Eigen::MatrixX3d points;
  double voxel = 0.0;  // the grid's edge; 0 when P was kept as it is
};

// P on a grid of edge `voxel` (0: none), then, while more than `maxPoints` (>= 8) remain, on
// grids 1.25 times coarser each, from the bounding box's diagonal / sqrt(maxPoints) / 2 (or from
// 1.25 `voxel`) up; P itself where it has `maxPoints` or fewer and no `voxel` is given.
ThinnedPoints thinToAtMost(const Eigen::MatrixX3d& P, int maxPoints, double voxel = 0.0);

}  // namespace bcassim
