// Where a polyline crosses a cutting plane (thesis §4.3.3): the curves of the atlas have no
// common parametrisation, so they are compared through their intersections with planes.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/atlas/CuttingPlanes.h"

namespace bcassim {

struct PlaneHit {
  Eigen::Vector3d point;  // intersection (m)
  double position;        // along the polyline: segment index + fraction in [0, 1)
};

// Crossings of the polyline (rows of points, in order) with the plane, in polyline order; a vertex
// lying exactly on the plane counts once. Radial half-planes keep only hits on their side.
std::vector<PlaneHit> intersectPolyline(const Eigen::MatrixX3d& points, const CuttingPlane& plane);

}  // namespace bcassim
