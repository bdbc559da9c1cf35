// Catching a point cloud in millimetres given for a surface in metres (or the other way round)
// from the sizes alone, before a registration silently fails on it.
#pragma once
#include <Eigen/Core>

#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// Bounding-box diagonal of the rows of P (#P by 3), in their units; 0 for fewer than 2 rows.
double boundingBoxDiagonal(const Eigen::MatrixX3d& P);

// A partial view covers part of the surface, so its bounding-box diagonal is some 0.1 to 1.5
// times the surface's; a unit mix-up makes it ~1000 or ~1/1000 times. Ratios beyond 30 or below
// 1/30 throw InputError naming both diagonals, e.g. "point cloud bounding-box diagonal 183.2 but
// the surface's is 0.2731 (ratio 670.8): the points look like millimetres for a surface in
// metres; expected both in metres". Also throws when the points have no extent.
void requireMatchingUnits(const Eigen::MatrixX3d& points, const TriMesh& surface);

}  // namespace bcassim
