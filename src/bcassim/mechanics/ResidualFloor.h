// The absolute floor under a force-residual tolerance: the round-off with which the internal
// forces themselves are computed, below which no Newton iteration can make progress.
#pragma once
#include <limits>

#include "bcassim/Types.h"

namespace bcassim {

// Round-off of f_int(x) in N. F = sum_a x_a grad N_a^T is built from absolute positions, so each
// entry carries an error of about eps |x|_max |grad N|, which the stiffness (dF -> df) turns into
// eps |x|_max K_ii on each dof: over all dofs, eps |x|_max |diag K|. Measured, the residual that
// Newton stalls at is 0.02 (a 930-node cylinder at rest) to 0.2 (a stretched membrane) of that;
// the factor 10 leaves a margin and still stays below the tolerance of every example scene (the
// closest: the membrane's first load step, 1e-9 of 0.25 N, is 3.7 times the floor), so that only
// round-off is ever taken for converged.
inline double forceRoundOff(double stiffnessDiagonalNorm, const Eigen::VectorXd& x) {
  constexpr double kMargin = 10.0;
  return kMargin * std::numeric_limits<double>::epsilon() * x.cwiseAbs().maxCoeff() *
         stiffnessDiagonalNorm;
}
inline double forceRoundOff(const SparseMatrix& K, const Eigen::VectorXd& x) {
  return forceRoundOff(K.diagonal().norm(), x);
}

}  // namespace bcassim
