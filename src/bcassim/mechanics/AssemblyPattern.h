// The fixed sparsity pattern of a 3N x 3N stiffness-like matrix on a tet mesh, computed once, with
// each tet's 12x12 block pre-mapped to value slots so assembly is a plain scatter (no triplet
// sort).
#pragma once
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

class AssemblyPattern {
 public:
  explicit AssemblyPattern(const TetMesh& mesh);
  // The tets' pattern plus every pair of nodes within each of `cliques` (node sets coupled by one
  // term, e.g. the patches of mean dilatation), whose (3m)x(3m) blocks are pre-mapped too.
  AssemblyPattern(const TetMesh& mesh, const std::vector<std::vector<int>>& cliques);

  // A matrix with the full (both triangles) pattern and zero values; assemble into copies of it.
  const SparseMatrix& emptyMatrix() const { return empty_; }
  // 144 value slots of tet t's block, row-major over local dofs: slot[(3a+i)*12 + 3b+j] is the
  // index into valuePtr() of entry (3*T(t,a)+i, 3*T(t,b)+j).
  const int* tetSlots(Eigen::Index t) const { return slots_.data() + 144 * t; }
  // (3m)^2 value slots of clique c's block (m nodes, in the order given), row-major over local
  // dofs.
  const int* cliqueSlots(int c) const { return cliqueSlots_.data() + cliqueStart_[c]; }
  // Value slot of the diagonal entry of dof d.
  int diagonalSlot(Eigen::Index d) const { return diagonal_[d]; }
  Eigen::Index numDofs() const { return empty_.rows(); }

 private:
  SparseMatrix empty_;
  std::vector<int> slots_;
  std::vector<int> diagonal_;
  std::vector<int> cliqueSlots_;
  std::vector<size_t> cliqueStart_;
};

// Adds a 12x12 tet block to A (which must have the pattern's structure).
inline void scatterTetBlock(const AssemblyPattern& pattern, Eigen::Index t, const Mat12& block,
                            SparseMatrix& A) {
  const int* slot = pattern.tetSlots(t);
  double* values = A.valuePtr();
  for (int r = 0; r < 12; ++r)
    for (int c = 0; c < 12; ++c) values[slot[12 * r + c]] += block(r, c);
}

}  // namespace bcassim
