// Reading a rigid motion written as a 4 x 4 homogeneous matrix (rotation and translation in
// metres): what `bcassim register` writes, NumPy's savetxt/save of a 4 x 4 array, Open3D's and
// most trackers' exports.
#pragma once
#include <string>

#include "bcassim/mesh/RigidTransform.h"

namespace bcassim {

// .csv (comma-separated) or .txt (blank-separated): four rows of four numbers, '#' comments and
// blank lines skipped; .npy: a (4, 4) numeric array. The last row must be 0 0 0 1 and the upper
// left 3 x 3 a rotation: R^T R within 1e-3 of the identity (a matrix written to a few digits) and
// det R > 0; the nearest rotation is used (polar decomposition). Throws InputError with one line
// naming the file (and line), e.g. "T.txt: the upper-left 3 x 3 scales lengths by 0.001, not a
// rotation (a change of units?); expected a rigid transform in metres".
RigidTransform readRigidTransform(const std::string& path);

}  // namespace bcassim
