#include "bcassim/assimilation/CanonicalSigmaPoints.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

SigmaPointSet canonicalSigmaPoints(Eigen::Index n) {
  if (n < 1) throw InputError(fmt::format("canonical sigma points need n >= 1, got {}", n));
  const double scale = std::sqrt(static_cast<double>(n));
  SigmaPointSet set;
  set.unit.setZero(n, 2 * n);
  set.weights.setConstant(2 * n, 1.0 / (2.0 * n));
  set.nonzeroRow.resize(static_cast<size_t>(2 * n));
  for (Eigen::Index k = 0; k < n; ++k) {
    set.unit(k, k) = scale;
    set.unit(k, n + k) = -scale;
    set.nonzeroRow[static_cast<size_t>(k)] = set.nonzeroRow[static_cast<size_t>(n + k)] = k;
  }
  set.structure = UnitStructure::SignedColumns;
  return set;
}

}  // namespace bcassim
