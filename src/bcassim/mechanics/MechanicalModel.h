// Everything that defines the mechanics of one organ model: mesh, elasticity, mass, ligament
// springs, loads, control points, Dirichlet conditions and Rayleigh damping, wired by the caller.
// It evaluates forces and stiffness; the integrators decide what to do with them.
#pragma once
#include <memory>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mechanics/AssemblyPattern.h"
#include "bcassim/mechanics/CubicSpringSet.h"
#include "bcassim/mechanics/DirichletConditions.h"
#include "bcassim/mechanics/Loads.h"
#include "bcassim/mechanics/MassMatrix.h"
#include "bcassim/mechanics/TetElasticity.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// Positions (m), velocities (m/s), both 3N node-major, and time (s).
struct MechanicalState {
  Eigen::VectorXd x, v;
  double t = 0.0;
};

struct MechanicalModel {
  // Shared, immutable between copies of the model (one copy per parallel worker).
  std::shared_ptr<const TetMesh> mesh;
  std::shared_ptr<const AssemblyPattern> pattern;

  TetElasticity elasticity;
  MassMatrix mass;
  CubicSpringSet springs;
  std::vector<NodalLoad> loads;
  std::vector<ControlPointSet> controls;
  DirichletConditions dirichlet;
  Vec3 gravity = Vec3::Zero();     // m/s^2
  double rayleighMass = 0.0;       // zeta_M, 1/s (eq. 2.15)
  double rayleighStiffness = 0.0;  // zeta_K, s

  // Rest state: x = rest positions, v = 0, t = 0, Dirichlet values imposed.
  MechanicalState restState() const;
  Eigen::VectorXd restPositions() const;

  // External forces at time t (N): nodal loads and gravity.
  void externalForces(double t, Eigen::VectorXd& f) const;
  // Internal (conservative) forces f_int = dW/dx at (x, t): elasticity, springs, control points.
  void internalForces(double t, const Eigen::VectorXd& x, Eigen::VectorXd& f) const;
  // The same with the elastic forces over `chunks` (TetElasticity::addInternalForces).
  void internalForces(double t, const Eigen::VectorXd& x, Eigen::VectorXd& f,
                      ChunkedForces& chunks) const;
  // f = f_int(x) and K = stiffness dW2/dx2 (K is reset to the pattern first).
  void internalForcesAndStiffness(double t, const Eigen::VectorXd& x, Eigen::VectorXd& f,
                                  SparseMatrix& K) const;
  // Stored energy W(x, t) = elastic + spring + control-point energy, J.
  double storedEnergy(double t, const Eigen::VectorXd& x) const;
};

// Builds the model's shared parts and members from a mesh and one material per region;
// meanDilatationPatchTets > 1 averages the volumetric term over patches of that many tets (see
// TetElasticity).
MechanicalModel makeMechanicalModel(std::shared_ptr<const TetMesh> mesh,
                                    std::vector<Material> regionMaterials, double density,
                                    MassKind massKind, int meanDilatationPatchTets = 1);

}  // namespace bcassim
