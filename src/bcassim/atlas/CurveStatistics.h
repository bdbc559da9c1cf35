// Mean and standard deviation of a set of curves plane by plane (thesis §4.3.3, §5.2): each curve
// is cut by every plane of a family and the crossing points of one plane are averaged.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/atlas/CuttingPlanes.h"

namespace bcassim {

// Centre of the crossing points of a plane: their mean (the thesis) or their geometric median
// (robust to a few misregistered curves).
enum class CurveCentre { Mean, Median };

struct PlaneStatistics {
  int count = 0;  // curves crossing the plane (one point each)
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // centre of the points (m): mean or median
  // Root-mean-square distance of the points to their Euclidean mean (m): the standard deviation
  // of the position, normalised by count (not count - 1).
  double sigma = 0.0;
  // Unit direction of largest spread of the points (zero when count < 2).
  Eigen::Vector3d spread = Eigen::Vector3d::Zero();
};

// One entry per plane of the family. A curve crossing a plane several times contributes the
// crossing closest to the centroid of all curves' crossings of that plane, so that each curve
// weighs once.
std::vector<PlaneStatistics> curveStatistics(const std::vector<Eigen::MatrixX3d>& curves,
                                             const CuttingPlaneFamily& planes,
                                             CurveCentre centre = CurveCentre::Mean);

}  // namespace bcassim
