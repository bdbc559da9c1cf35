// The truth of the spring calibration (thesis §2.3.4, Fig. 2.15 left): a thin hyperelastic strip
// of tetrahedra, its short edge at y = 0 clamped, the one at y = length held in x and z and pulled
// along y in quasi-static frames (Newton, StaticSolver). Lengths in metres, forces in newtons.
#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/StaticSolver.h"

namespace bcassim {

struct MembraneOptions {
  Vec3 size = Vec3(0.04, 0.1, 0.001);        // width (x), length (y), thickness (z), m
  std::string material = "neohookean";       // a name of makeMaterial (mechanics/materials)
  double young = 403e3;                      // Pa
  double poisson = 0.45;                     // -
  int cellsX = 16, cellsY = 40, cellsZ = 1;  // hexahedra of the mesh, 6 tets each
  double relativeTolerance = 1e-9;           // Newton's (StaticOptions::relativeTolerance)
};

class MembraneStrip {
 public:
  // Throws InputError for a non-positive size or cell count, or a bad material.
  explicit MembraneStrip(const MembraneOptions& options);

  // Equilibrium with the pulled edge at rest + d (m along y, 0 <= d <= length), from x (3N,
  // overwritten; e.g. the previous frame's equilibrium, or restPositions()). Returns the reaction
  // on the pulled edge along y (N, > 0 in tension). Throws StepFailure when Newton fails.
  double solve(double d, Eigen::VectorXd& x);
  Eigen::VectorXd restPositions() const { return model_.restPositions(); }
  // Mesh node at grid point (i, j, k) of the cells (0 <= i <= cellsX, ...).
  int node(int i, int j, int k) const;
  const TetMesh& mesh() const { return *model_.mesh; }
  int lastIterations() const { return iterations_; }

 private:
  MembraneOptions options_;
  MechanicalModel model_;
  std::unique_ptr<StaticSolver> solver_;
  std::vector<int> pulled_;
  int iterations_ = 0;
};

}  // namespace bcassim
