// Pairing a frame's detections with the tracks' predicted positions under a gating distance, by
// the optimal assignment or by the thesis' greedy baseline: the one step where the two differ.
#pragma once
#include <Eigen/Core>

#include "bcassim/tracking/Assignment.h"

namespace bcassim {

enum class AssignmentMethod {
  Optimal,  // global nearest neighbour: the cheapest pairing as a whole (Assignment.h)
  Greedy,   // the thesis' minimal distances first (GreedyAssignment.h), the baseline
};

// Rows: tracks, columns: detections; squaredDistances(i, j) is the squared distance (m^2) from
// track i's predicted position to detection j. No pair farther than `gate` (m) is made.
// Optimal: minimises the sum of the pairs' squared distances plus gate^2 / 2 for every track and
// every detection left unpaired, so a pair is made only where it is cheaper than leaving both
// alone; solved as one square assignment over tracks and detections with "unpaired" entries.
// Greedy: solveGreedyAssignment over the distances within the gate.
// Throws InputError for a non-positive gate or NaN distances.
Assignment matchWithinGate(const Eigen::MatrixXd& squaredDistances, double gate,
                           AssignmentMethod method);

}  // namespace bcassim
