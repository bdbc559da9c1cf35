// Checks a tetrahedral mesh read from a file before anything computes on it: finite coordinates,
// indices in range, no degenerate or inverted tets. Errors name the source and the offending item.
#pragma once
#include <string>

#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// Signed volume of tet t, (b-a)x(c-a).(d-a)/6, m^3.
double signedVolume(const TetMesh& mesh, Eigen::Index t);

// Validates `mesh` read from `source` (a file name, used in messages) and normalises orientation:
// if every tet is negatively oriented (a file written with the opposite convention) all are
// flipped; a mesh mixing orientations has inverted tets and is rejected. Throws InputError, e.g.
// "liver.vtk: tet 17 is inverted (signed volume -1.2e-09 m^3); expected positive orientation".
void validateTetMesh(TetMesh& mesh, const std::string& source);

}  // namespace bcassim
