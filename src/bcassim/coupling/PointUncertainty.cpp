#include "bcassim/coupling/PointUncertainty.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

std::vector<PointUncertainty> pointUncertainty(const TetMesh& mesh,
                                               const std::vector<MappedPoint>& points,
                                               const Eigen::MatrixXd& factor) {
  if (factor.rows() < 3 * mesh.numNodes())
    throw InputError(fmt::format(
        "point uncertainty needs the node positions in the filter state ({} rows, got {}): set "
        "assimilation.state.positions: true",
        3 * mesh.numNodes(), factor.rows()));
  std::vector<PointUncertainty> out(points.size());
  Eigen::MatrixXd rows(3, factor.cols());
  for (size_t p = 0; p < points.size(); ++p) {
    rows.setZero();
    for (int k = 0; k < 4; ++k)
      rows += points[p].weights(k) * factor.middleRows(3 * mesh.T(points[p].tet, k), 3);
    PointUncertainty& u = out[p];
    u.covariance = rows * rows.transpose();
    u.sigma = u.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
    const double lambda =
        Eigen::SelfAdjointEigenSolver<Mat3>(u.covariance).eigenvalues().maxCoeff();
    u.radius95 = std::sqrt(kChiSquare3At95 * std::max(lambda, 0.0));
  }
  return out;
}

}  // namespace bcassim
