// Quasi-static stretch of a spring lattice (the model side of thesis Fig. 2.15): the nodes at
// y = 0 clamped, those at y = length held in x and z and moved by d along y; equilibrium of the
// free nodes by Newton on the lattice's energy with a backtracking line search.
#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <array>
#include <vector>

#include "bcassim/calibration/SpringLattice.h"

namespace bcassim {

struct LatticeStretchOptions {
  // Newton stops at |f_free| <= relativeTolerance * |reaction| (N).
  double relativeTolerance = 1e-9;
  int maxIterations = 100;
};

class LatticeStretch {
 public:
  // The lattice must outlive this object.
  explicit LatticeStretch(const SpringLattice& lattice, LatticeStretchOptions options = {});

  // Equilibrium with the pulled end at rest + d (m, along y) and coefficients k, starting from x
  // (3N positions, overwritten; e.g. the equilibrium of the previous frame, or the rest
  // positions): the free nodes first follow the change of d affinely along y. Returns the
  // reaction on the pulled end along y (N, > 0 in tension). Throws NumericalError when Newton
  // does not converge.
  double solve(const CubicSpringCoefficients& k, double d, Eigen::VectorXd& x);
  // The reaction (N, along y) on the pulled end's nodes at positions x.
  double reaction(const CubicSpringCoefficients& k, const Eigen::VectorXd& x) const;
  // Newton iterations of the last solve.
  int iterations() const { return iterations_; }
  const std::vector<int>& pulledNodes() const { return pulled_; }
  // Nodes neither clamped nor pulled.
  const std::vector<int>& freeNodes() const { return freeNodes_; }

 private:
  const SpringLattice* lattice_;
  LatticeStretchOptions options_;
  std::vector<int> pulled_, freeNodes_;
  std::vector<int> freeIndex_;  // per dof: index among the free dofs, or -1
  int numFree_ = 0;
  int iterations_ = 0;
  Eigen::VectorXd f_;
  // The free dofs' stiffness, its pattern fixed (every spring's blocks, slack or not) and analysed
  // once; per spring the value slots of its blocks aa, bb, ab, ba (9 each, row-major, -1 where a
  // dof is not free); the diagonal's slots.
  SparseMatrix K_;
  std::vector<std::array<int, 36>> slots_;
  std::vector<int> diagonal_;
  Eigen::SimplicialLDLT<SparseMatrix> ldlt_;
};

}  // namespace bcassim
