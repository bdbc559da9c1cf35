// Canonical sigma points (thesis eq. 3.5): +-sqrt(n) e_k with weights 1/(2n), 2n points.
#pragma once
#include "bcassim/assimilation/SigmaPointSet.h"

namespace bcassim {

// Throws InputError for n < 1.
SigmaPointSet canonicalSigmaPoints(Eigen::Index n);

}  // namespace bcassim
