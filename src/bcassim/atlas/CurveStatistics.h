// Mean and standard deviation of a set of curves plane by plane (thesis §4.3.3, §5.2): each curve
// is cut by every plane of a family and the crossing points of one plane are averaged.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/atlas/CuttingPlanes.h"

namespace bcassim {

// Centre of the crossing points of a plane: their mean (the thesis), their geometric median
// (robust to a few misregistered curves), or the mean of the points that remain after rejecting
// outliers with the Hampel identifier (Trimmed): a point is rejected when its distance to the
// plane's geometric median exceeds k robust standard deviations, the robust standard deviation
// being 1.4826 times the median of those distances (the MAD, scaled to be consistent for normal
// scatter along one direction: the crossings of one plane spread along the surface within it).
// Trimmed keeps the mean's efficiency on the typical curves while a few atypical or misregistered
// training curves can no longer pull it; its sigma is the spread of the points kept.
enum class CurveCentre { Mean, Median, Trimmed };

// Default k of the Hampel identifier (3 MADs: a normal point is rejected with probability 0.3 %).
inline constexpr double kDefaultOutlierMads = 3.0;

struct PlaneStatistics {
  int count = 0;  // curves crossing the plane (one point each)
  int kept = 0;   // of these, points the centre and sigma were computed from (Trimmed: inliers)
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // centre of the points (m): mean or median
  // Root-mean-square distance of the (kept) points to their Euclidean mean (m): the standard
  // deviation of the position, normalised by kept (not kept - 1).
  double sigma = 0.0;
  // Unit direction of largest spread of the (kept) points (zero when kept < 2).
  Eigen::Vector3d spread = Eigen::Vector3d::Zero();
};

// One entry per plane of the family. A curve crossing a plane several times contributes the
// crossing closest to the centroid of all curves' crossings of that plane, so that each curve
// weighs once. outlierMads: k of CurveCentre::Trimmed (> 0), ignored otherwise.
std::vector<PlaneStatistics> curveStatistics(const std::vector<Eigen::MatrixX3d>& curves,
                                             const CuttingPlaneFamily& planes,
                                             CurveCentre centre = CurveCentre::Mean,
                                             double outlierMads = kDefaultOutlierMads);

// Indices of the points kept by the Hampel identifier: distance to their geometric median at most
// k * 1.4826 * (median of those distances). All points when fewer than 3; when that median is
// zero (half the points or more coincide), only the points at the median; all points when none
// passes (possible for k < 0.68). Throws InputError when k <= 0.
std::vector<int> hampelInliers(const std::vector<Eigen::Vector3d>& points, double k);

}  // namespace bcassim
