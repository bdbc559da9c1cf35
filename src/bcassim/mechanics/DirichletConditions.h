// Dirichlet boundary conditions: node sets held at rest position + displacement * profile(t), and
// their elimination from a linear system in place (identity rows/columns, fixed sparsity pattern).
#pragma once
#include <array>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mechanics/AssemblyPattern.h"
#include "bcassim/mechanics/TimeProfile.h"

namespace bcassim {

struct DirichletRegion {
  std::vector<int> nodes;
  Vec3 displacement = Vec3::Zero();                     // m; zero means fixed
  TimeProfile profile;                                  // multiplies displacement
  std::array<bool, 3> components = {true, true, true};  // which of x, y, z are prescribed
};

class DirichletConditions {
 public:
  DirichletConditions() = default;
  DirichletConditions(std::vector<DirichletRegion> regions, const AssemblyPattern& pattern);

  bool empty() const { return dofs_.empty(); }
  const std::vector<int>& constrainedDofs() const { return dofs_; }
  // Prescribed positions of the constrained dofs at time t, in constrainedDofs() order.
  Eigen::VectorXd targetPositions(const Eigen::VectorXd& restPositions, double t) const;
  // Sets x to its prescribed values at time t.
  void impose(const Eigen::VectorXd& restPositions, double t, Eigen::VectorXd& x) const;

  // Turns A y = b into the system with y_d = known_d on constrained dofs d (known in
  // constrainedDofs() order): moves known columns to the right-hand side, then makes the rows and
  // columns identity. A must have the pattern's structure.
  void eliminate(SparseMatrix& A, Eigen::VectorXd& b, const Eigen::VectorXd& known) const;
  // The two halves of eliminate(): the right-hand side, from A as it was before elimination (so
  // that one eliminated matrix can serve many right-hand sides), and the matrix alone.
  void eliminateRightHandSide(const SparseMatrix& A, Eigen::VectorXd& b,
                              const Eigen::VectorXd& known) const;
  void eliminateMatrix(SparseMatrix& A) const;
  // Zeros the constrained entries of a vector (residuals, forces).
  void zeroConstrained(Eigen::VectorXd& v) const {
    for (int d : dofs_) v(d) = 0.0;
  }

 private:
  std::vector<DirichletRegion> regions_;
  std::vector<int> dofs_;         // sorted, unique
  std::vector<int> regionOfDof_;  // which region prescribes each dof (last one wins)
  std::vector<int> slotsToZero_;  // value slots in a constrained row or column
  std::vector<int> diagonalSlots_;
  std::vector<char> isConstrained_;
};

}  // namespace bcassim
