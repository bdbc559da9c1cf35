// Optimal assignment of rows to columns of a rectangular cost matrix with forbidden pairs: the
// shortest-augmenting-path Hungarian method (Jonker-Volgenant style), O(n^2 m) for n <= m.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace bcassim {

// A matching of rows to columns, each used at most once.
struct Assignment {
  std::vector<int> columnOfRow;  // #rows: the column paired with each row, or -1
  std::vector<int> rowOfColumn;  // #columns: the row paired with each column, or -1
  double cost = 0.0;             // sum of the costs of the pairs made
  int numPairs() const;
};

// Pairs rows with columns of `cost` (any shape, entries finite or +infinity for a forbidden
// pair) so that the number of pairs is the largest possible without forbidden pairs and, among
// such matchings, the summed cost is the smallest. Ties are broken deterministically. Throws
// InputError naming the entry when an entry is NaN or -infinity.
Assignment solveOptimalAssignment(const Eigen::MatrixXd& cost);

// Throws InputError "assignment: cost (i, j) is nan; expected ..." for the first NaN or
// -infinity entry: the check every assignment method makes of its input.
void requireAssignmentCosts(const Eigen::MatrixXd& cost);

}  // namespace bcassim
