#include "bcassim/assimilation/StarSigmaPoints.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

SigmaPointSet starSigmaPoints(Eigen::Index n, double kappa) {
  if (n < 1 || !(kappa >= 0))
    throw InputError(
        fmt::format("star sigma points need n >= 1 and kappa >= 0, got {} and {}", n, kappa));
  const double scale = std::sqrt(n + kappa);
  SigmaPointSet set;
  set.unit.setZero(n, 2 * n + 1);
  set.weights.setConstant(2 * n + 1, 1.0 / (2.0 * (n + kappa)));
  set.weights[0] = kappa / (n + kappa);
  set.nonzeroRow.assign(static_cast<size_t>(2 * n + 1), -1);
  for (Eigen::Index k = 0; k < n; ++k) {
    set.unit(k, 1 + k) = scale;
    set.unit(k, 1 + n + k) = -scale;
    set.nonzeroRow[static_cast<size_t>(1 + k)] = set.nonzeroRow[static_cast<size_t>(1 + n + k)] = k;
  }
  set.structure = UnitStructure::SignedColumns;
  return set;
}

}  // namespace bcassim
