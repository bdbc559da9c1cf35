// Per-tet von Mises equivalent of the Cauchy stress, for colouring ParaView output.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mechanics/TetElasticity.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

class StressField {
 public:
  // Precomputes the inverse rest edge matrices of `mesh`.
  explicit StressField(const TetMesh& mesh);

  // von Mises stress sqrt(3/2 s:s) of the Cauchy stress sigma = P F^T / J in each tet (Pa) at
  // positions x (3N, m). Inverted tets (det F <= 0) get 0, the linear law's included: sigma
  // divides by J.
  Eigen::VectorXd vonMises(const TetMesh& mesh, const TetElasticity& elasticity,
                           const Eigen::VectorXd& x) const;

 private:
  std::vector<Mat3> restInverse_;
};

}  // namespace bcassim
