// The "vessels" fixed region of a liver model: nodes near the hilum / inferior vena cava, where
// the vessels hold the liver, selected as a ball around a user-given or guessed point. Metres.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// Sorted ids of the nodes within `radius` (m) of `center`.
std::vector<int> nodesWithinRadius(const TetMesh& mesh, const Vec3& center, double radius);

// Heuristic hilum point when none is given: among boundary nodes, keep the `farFraction` farthest
// from the ligament curve (#P by 3, m; the falciform ligament lies anteriorly and superiorly,
// the hilum and IVC posteriorly and inferiorly), and return the one farthest along `posterior`
// (a direction in the mesh frame, e.g. +y in a CT's LPS frame). Throws InputError for an empty
// mesh or curve, a zero direction, or farFraction outside (0, 1].
Vec3 guessHilumPoint(const TetMesh& mesh, const Eigen::MatrixX3d& curve, const Vec3& posterior,
                     double farFraction = 0.25);

}  // namespace bcassim
