// Mass matrix of a P1 tet mesh with uniform density: lumped (rho V / 4 per node) or consistent
// (rho V / 20 (1 + delta_ab) per dof direction), in the assembly pattern's structure.
#pragma once
#include "bcassim/Types.h"
#include "bcassim/mechanics/AssemblyPattern.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

enum class MassKind { Lumped, Consistent };

class MassMatrix {
 public:
  // density in kg/m^3.
  MassMatrix(const TetMesh& mesh, const AssemblyPattern& pattern, double density, MassKind kind);

  MassKind kind() const { return kind_; }
  // out = M v (v, out: 3N).
  void multiply(const Eigen::VectorXd& v, Eigen::VectorXd& out) const;
  // A += scale * M (A has the pattern's structure).
  void addTo(const AssemblyPattern& pattern, double scale, SparseMatrix& A) const;
  double kineticEnergy(const Eigen::VectorXd& v) const;  // 1/2 v^T M v, J
  double totalMass() const { return totalMass_; }        // kg
  // Lumped mass per dof (the row sums of M for a consistent matrix), kg.
  const Eigen::VectorXd& lumpedDiagonal() const { return lumped_; }

 private:
  MassKind kind_;
  double totalMass_ = 0;
  Eigen::VectorXd lumped_;
  SparseMatrix consistent_;  // empty when lumped
};

}  // namespace bcassim
