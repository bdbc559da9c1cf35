// Star sigma points (thesis eq. 3.4): the centre and +-sqrt(n+kappa) e_k, 2n+1 points.
#pragma once
#include "bcassim/assimilation/SigmaPointSet.h"

namespace bcassim {

// Column 0 is the centre (the mean itself), so with firstSigmaPointAlone the forecast run alone is
// the mean's. kappa = 0 is eq. 3.4 literally (scale sqrt(n), centre weight 0); kappa > 0 is
// Julier's variant with centre weight kappa/(n+kappa). Throws InputError for n < 1 or kappa < 0.
SigmaPointSet starSigmaPoints(Eigen::Index n, double kappa = 0.0);

}  // namespace bcassim
