// Linear (P1) tetrahedral mesh: rest positions, tets, and a region id per tet.
// Convention: each tet (a,b,c,d) is positively oriented, (b-a)x(c-a).(d-a) > 0.
#pragma once
#include <Eigen/Core>

namespace bcassim {
struct TetMesh {
  Eigen::MatrixX3d V;      // #V by 3 rest positions, metres
  Eigen::MatrixX4i T;      // #T by 4 node indices
  Eigen::VectorXi region;  // #T region id (0 when the mesh has none); empty means all 0

  Eigen::Index numNodes() const { return V.rows(); }
  Eigen::Index numTets() const { return T.rows(); }
  int regionOf(Eigen::Index t) const { return region.size() ? region(t) : 0; }
};
}  // namespace bcassim
