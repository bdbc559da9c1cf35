#include "bcassim/tracking/GatedMatching.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "bcassim/Error.h"
#include "bcassim/tracking/GreedyAssignment.h"

namespace bcassim {

Assignment matchWithinGate(const Eigen::MatrixXd& squaredDistances, double gate,
                           AssignmentMethod method) {
  if (!(gate > 0.0) || !std::isfinite(gate))
    throw InputError(fmt::format("gate {} m; expected a positive finite distance (m)", gate));
  requireAssignmentCosts(squaredDistances);
  constexpr double kForbidden = std::numeric_limits<double>::infinity();
  const double gate2 = gate * gate;
  const Eigen::Index tracks = squaredDistances.rows(), detections = squaredDistances.cols();
  const Eigen::MatrixXd gated =
      squaredDistances.unaryExpr([&](double d2) { return d2 <= gate2 ? d2 : kForbidden; });
  if (method == AssignmentMethod::Greedy) return solveGreedyAssignment(gated);

  // [ gated      | unpaired tracks (diagonal) ]
  // [ unpaired   | 0                          ]
  //   detections
  const Eigen::Index n = tracks + detections;
  Eigen::MatrixXd extended = Eigen::MatrixXd::Constant(n, n, kForbidden);
  extended.topLeftCorner(tracks, detections) = gated;
  for (Eigen::Index i = 0; i < tracks; ++i) extended(i, detections + i) = 0.5 * gate2;
  for (Eigen::Index j = 0; j < detections; ++j) extended(tracks + j, j) = 0.5 * gate2;
  extended.bottomRightCorner(detections, tracks).setZero();
  const Assignment full = solveOptimalAssignment(extended);

  Assignment result;
  result.columnOfRow.assign(tracks, -1);
  result.rowOfColumn.assign(detections, -1);
  for (Eigen::Index i = 0; i < tracks; ++i) {
    const int j = full.columnOfRow[i];
    if (j < 0 || j >= detections) continue;
    result.columnOfRow[i] = j;
    result.rowOfColumn[j] = static_cast<int>(i);
    result.cost += gated(i, j);
  }
  return result;
}

}  // namespace bcassim
