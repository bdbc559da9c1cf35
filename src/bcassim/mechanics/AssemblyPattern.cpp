#include "bcassim/mechanics/AssemblyPattern.h"

#include <algorithm>

namespace bcassim {

AssemblyPattern::AssemblyPattern(const TetMesh& mesh) : AssemblyPattern(mesh, {}) {}

AssemblyPattern::AssemblyPattern(const TetMesh& mesh,
                                 const std::vector<std::vector<int>>& cliques) {
  const Eigen::Index n = mesh.numNodes();
  // Node adjacency (including self) from the tets and cliques; each node pair expands to a 3x3
  // block.
  std::vector<std::vector<int>> adjacent(n);
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) adjacent[mesh.T(t, a)].push_back(mesh.T(t, b));
  for (const auto& clique : cliques)
    for (int a : clique)
      for (int b : clique) adjacent[a].push_back(b);
  for (Eigen::Index i = 0; i < n; ++i) {
    auto& adj = adjacent[i];
    adj.push_back(static_cast<int>(i));
    std::sort(adj.begin(), adj.end());
    adj.erase(std::unique(adj.begin(), adj.end()), adj.end());
  }

  const Eigen::Index dofs = 3 * n;
  empty_.resize(dofs, dofs);
  Eigen::VectorXi nnzPerCol(dofs);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int j = 0; j < 3; ++j) nnzPerCol(3 * i + j) = 3 * static_cast<int>(adjacent[i].size());
  empty_.reserve(nnzPerCol);
  // Columns of node i hold rows of its neighbours in increasing order, so insertion is sequential.
  for (Eigen::Index i = 0; i < n; ++i)
    for (int cj = 0; cj < 3; ++cj)
      for (int nb : adjacent[i])
        for (int ri = 0; ri < 3; ++ri) empty_.insert(3 * nb + ri, 3 * i + cj) = 0.0;
  empty_.makeCompressed();

  // Slot of (row, col): binary search in the column's sorted row indices (done once).
  const int* outer = empty_.outerIndexPtr();
  const int* inner = empty_.innerIndexPtr();
  auto slotOf = [&](int row, int col) {
    const int* first = inner + outer[col];
    const int* last = inner + outer[col + 1];
    return static_cast<int>(std::lower_bound(first, last, row) - inner);
  };
  slots_.resize(144 * mesh.numTets());
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    int* s = slots_.data() + 144 * t;
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i)
        for (int b = 0; b < 4; ++b)
          for (int j = 0; j < 3; ++j)
            s[(3 * a + i) * 12 + 3 * b + j] = slotOf(3 * mesh.T(t, a) + i, 3 * mesh.T(t, b) + j);
  }
  cliqueStart_.reserve(cliques.size());
  for (const auto& clique : cliques) {
    cliqueStart_.push_back(cliqueSlots_.size());
    const int m = static_cast<int>(clique.size());
    for (int a = 0; a < m; ++a)
      for (int i = 0; i < 3; ++i)
        for (int b = 0; b < m; ++b)
          for (int j = 0; j < 3; ++j)
            cliqueSlots_.push_back(slotOf(3 * clique[a] + i, 3 * clique[b] + j));
  }
  diagonal_.resize(dofs);
  for (Eigen::Index d = 0; d < dofs; ++d)
    diagonal_[d] = slotOf(static_cast<int>(d), static_cast<int>(d));
}

}  // namespace bcassim
