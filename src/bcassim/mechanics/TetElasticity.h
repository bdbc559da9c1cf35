// Hyperelastic P1 tetrahedral finite elements: elastic energy, internal forces f = dW/dx and
// stiffness K = d2W/dx2 of the whole mesh (thesis eq. 2.7-2.12), one material per mesh region.
#pragma once
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mechanics/AssemblyPattern.h"
#include "bcassim/mechanics/materials/Material.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

class TetElasticity {
 public:
  // regionMaterials[r] is the material of the tets whose region id is r (a single entry serves all
  // tets). Shape gradients and volumes are precomputed here from the rest positions.
  TetElasticity(const TetMesh& mesh, std::vector<Material> regionMaterials);

  // Total elastic energy at positions x (3N node-major, m), J.
  double energy(const Eigen::VectorXd& x) const;
  // Adds the internal forces f_int = dW/dx (N) at x to f.
  void addInternalForces(const Eigen::VectorXd& x, Eigen::VectorXd& f) const;
  // Adds f_int to f and scale * K(x) into K (K must have `pattern`'s structure).
  void addForcesAndStiffness(const Eigen::VectorXd& x, const AssemblyPattern& pattern, double scale,
                             Eigen::VectorXd& f, SparseMatrix& K) const;

  const Material& material(int region) const { return materials_[region]; }
  void setMaterial(int region, const Material& m) { materials_[region] = m; }
  int numRegions() const { return static_cast<int>(materials_.size()); }
  double restVolume(Eigen::Index t) const { return volume_[t]; }
  // Number of tets with det F <= 0 at positions x.
  Eigen::Index countInverted(const Eigen::VectorXd& x) const;
  // Number of tets with det F <= 0 met by the last force evaluation (0 in a healthy simulation).
  Eigen::Index lastInvertedCount() const { return inverted_; }

 private:
  template <class Visitor>
  void forEachRegion(Visitor&& visit) const;

  Eigen::MatrixX4i T_;
  std::vector<Eigen::Matrix<double, 4, 3>> gradN_;  // rows: grad of each node's shape function, 1/m
  std::vector<double> volume_;                      // rest volume per tet, m^3
  std::vector<Material> materials_;
  std::vector<std::vector<int>> tetsOfRegion_;
  mutable Eigen::Index inverted_ = 0;
};

}  // namespace bcassim
