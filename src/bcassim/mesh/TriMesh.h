// Triangle surface mesh (for STL/OBJ input, boundary surfaces, and atlas work).
// Convention: faces of a closed surface are ordered counter-clockwise seen from outside.
#pragma once
#include <Eigen/Core>

namespace bcassim {
struct TriMesh {
  Eigen::MatrixX3d V;  // #V by 3 vertex positions, metres (unless documented otherwise)
  Eigen::MatrixX3i F;  // #F by 3 vertex indices
};
}  // namespace bcassim
