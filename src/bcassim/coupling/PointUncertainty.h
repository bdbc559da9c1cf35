// Uncertainty of points embedded in the mesh (hidden tumours, vessels) from the filter's
// covariance: a point is a linear function of the node positions, so its 3x3 covariance is
// (H S)(H S)^T for any factor S of the state covariance. Metres.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mesh/BarycentricMap.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

struct PointUncertainty {
  Mat3 covariance = Mat3::Zero();  // m^2
  Vec3 sigma = Vec3::Zero();       // standard deviation along x, y, z, m
  // Radius of the sphere that holds the point with 95 % probability under the Gaussian model,
  // taken conservatively along the principal axis: sqrt(chi2_3(0.95) lambda_max), m.
  double radius95 = 0.0;
};

// chi-square quantile with 3 degrees of freedom at 0.95.
inline constexpr double kChiSquare3At95 = 7.814727903251178;

// `factor`: S with state covariance S S^T whose rows 3i .. 3i+2 are node i's position (rows past
// 3 #nodes are ignored). Throws InputError when S has fewer than 3 #nodes rows.
std::vector<PointUncertainty> pointUncertainty(const TetMesh& mesh,
                                               const std::vector<MappedPoint>& points,
                                               const Eigen::MatrixXd& factor);

}  // namespace bcassim
