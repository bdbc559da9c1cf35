// The thesis' frame-to-frame matching (§5.3), kept as the baseline to beat: pairs are taken in
// increasing cost, each from the rows and columns still free. Same interface as Assignment.h.
#pragma once
#include <Eigen/Core>

#include "bcassim/tracking/Assignment.h"

namespace bcassim {

// Repeatedly pairs the row and column of the smallest remaining finite cost (ties: lower row,
// then lower column) until no finite entry is left between free rows and columns. +infinity
// marks a forbidden pair. Not optimal in general. Throws InputError for NaN or -infinity.
Assignment solveGreedyAssignment(const Eigen::MatrixXd& cost);

}  // namespace bcassim
