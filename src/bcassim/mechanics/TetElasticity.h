// Hyperelastic P1 tetrahedral finite elements: elastic energy, internal forces f = dW/dx and
// stiffness K = d2W/dx2 of the whole mesh (thesis eq. 2.7-2.12), one material per mesh region,
// optionally with the volumetric term averaged over patches of tets (mean dilatation).
#pragma once
#include <memory>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mechanics/AssemblyPattern.h"
#include "bcassim/mechanics/ChunkedForces.h"
#include "bcassim/mechanics/InvertedElementError.h"
#include "bcassim/mechanics/MeanDilatationPatches.h"
#include "bcassim/mechanics/materials/Material.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

class TetElasticity {
 public:
  // regionMaterials[r] is the material of the tets whose region id is r (a single entry serves all
  // tets). Shape gradients and volumes are precomputed here from the rest positions.
  // meanDilatationPatchTets > 1 replaces each tet's volumetric term lambda/2 theta(F)^2 (theta =
  // tr E for StVK, ln J for Neo-Hookean) by lambda/2 V_P thetabar^2 per patch of that many tets,
  // thetabar the patch's volume average of theta: the same energy for every affine deformation,
  // far less volumetric locking at Poisson ratios near 0.5. The stiffness then couples all nodes of
  // a patch: assemble into a pattern made with patchNodeSets(). Throws InputError when a material
  // has no such split (only stvk and neohookean have).
  TetElasticity(const TetMesh& mesh, std::vector<Material> regionMaterials,
                int meanDilatationPatchTets = 1);

  // Total elastic energy at positions x (3N node-major, m), J.
  double energy(const Eigen::VectorXd& x) const;
  // Adds the internal forces f_int = dW/dx (N) at x to f. Throws InvertedElementError, once the
  // whole mesh is assembled, if a tet has det F <= 0 under a law that takes no inverted state
  // (every law but the linear one, see HyperelasticMaterial.h: no such state is taken as a
  // result). Linear tets are evaluated wherever they go.
  void addInternalForces(const Eigen::VectorXd& x, Eigen::VectorXd& f) const;
  // The same over the fixed chunks of `chunks` (on its threads; the same bits for any number of
  // them, differing from the loop above by round-off). Mean-dilatation patches stay on this thread.
  void addInternalForces(const Eigen::VectorXd& x, Eigen::VectorXd& f, ChunkedForces& chunks) const;
  // Adds f_int to f and scale * K(x) into K (K must have `pattern`'s structure). Throws
  // InvertedElementError as addInternalForces.
  void addForcesAndStiffness(const Eigen::VectorXd& x, const AssemblyPattern& pattern, double scale,
                             Eigen::VectorXd& f, SparseMatrix& K) const;

  const Material& material(int region) const { return materials_[region]; }
  void setMaterial(int region, const Material& m) { materials_[region] = m; }
  int numRegions() const { return static_cast<int>(materials_.size()); }
  double restVolume(Eigen::Index t) const { return volume_[t]; }
  // Number of tets with det F <= 0 at positions x whose law takes no inverted state (linear
  // tets are never counted).
  Eigen::Index countInverted(const Eigen::VectorXd& x) const;
  // Throws InvertedElementError if such a tet has det F <= 0 at positions x: the check of a state
  // that no force evaluation has seen (the end of a linearised step). About a tenth of a force
  // assembly (det F from the edge vectors' triple product, no material law).
  void requireNoInverted(const Eigen::VectorXd& x) const;
  // Number of such tets met by the last force evaluation (0 in a healthy simulation).
  Eigen::Index lastInvertedCount() const { return inverted_; }
  // The nodes of each mean-dilatation patch (empty without mean dilatation): the cliques the
  // assembly pattern must hold.
  const std::vector<std::vector<int>>& patchNodeSets() const;
  bool hasMeanDilatation() const { return patches_ != nullptr; }

 private:
  template <class Visitor>
  void forEachRegion(Visitor&& visit) const;
  template <class Visitor>
  void forEachPatchRegion(Visitor&& visit) const;
  template <class Visitor>
  void forEachTetThatMustNotInvert(Visitor&& visit) const;
  // Mean-dilatation versions of the three evaluations (K and pattern null for forces only).
  double patchEnergy(const Eigen::VectorXd& x) const;
  void addPatchForcesAndStiffness(const Eigen::VectorXd& x, const AssemblyPattern* pattern,
                                  double scale, Eigen::VectorXd& f, SparseMatrix* K) const;

  Eigen::MatrixX4i T_;
  std::vector<Eigen::Matrix<double, 4, 3>> gradN_;  // rows: grad of each node's shape function, 1/m
  std::vector<double> volume_;                      // rest volume per tet, m^3
  std::vector<Material> materials_;
  std::vector<std::vector<int>> tetsOfRegion_;
  std::vector<int> regionOfTet_;                          // empty with a single material
  std::shared_ptr<const MeanDilatationPatches> patches_;  // null: plain elements
  std::vector<std::vector<int>> patchesOfRegion_;
  mutable Eigen::Index inverted_ = 0;
};

}  // namespace bcassim
