// Simplex sigma points (thesis eq. 3.6, Julier's spherical simplex as used by the ROUKF, Alg. 2):
// n+1 points equidistant from the mean, equal weights 1/(n+1).
#pragma once
#include "bcassim/assimilation/SigmaPointSet.h"

namespace bcassim {

// Built by the recursion of eq. 3.6: dimension j adds coordinate c_j = 1/sqrt(j(j+1)w) to the j
// existing points and a new point with -j c_j, which keeps the mean at 0 and makes the weighted
// second moment the identity. Throws InputError for n < 1.
SigmaPointSet simplexSigmaPoints(Eigen::Index n);

}  // namespace bcassim
