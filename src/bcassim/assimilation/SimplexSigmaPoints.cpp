#include "bcassim/assimilation/SimplexSigmaPoints.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

SigmaPointSet simplexSigmaPoints(Eigen::Index n) {
  if (n < 1) throw InputError(fmt::format("simplex sigma points need n >= 1, got {}", n));
  const double w = 1.0 / static_cast<double>(n + 1);
  SigmaPointSet set;
  set.unit.setZero(n, n + 1);
  set.weights.setConstant(n + 1, w);
  for (Eigen::Index j = 1; j <= n; ++j) {
    const double c = 1.0 / std::sqrt(j * (j + 1.0) * w);
    set.unit.row(j - 1).head(j).setConstant(c);
    set.unit(j - 1, j) = -static_cast<double>(j) * c;
  }
  set.structure = UnitStructure::Simplex;
  return set;
}

}  // namespace bcassim
