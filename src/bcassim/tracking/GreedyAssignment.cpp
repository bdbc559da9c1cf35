#include "bcassim/tracking/GreedyAssignment.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

namespace bcassim {

Assignment solveGreedyAssignment(const Eigen::MatrixXd& cost) {
  struct Pair {
    double cost;
    int row, column;
  };
  requireAssignmentCosts(cost);
  std::vector<Pair> pairs;
  for (int j = 0; j < cost.cols(); ++j)
    for (int i = 0; i < cost.rows(); ++i) {
      if (std::isfinite(cost(i, j))) pairs.push_back({cost(i, j), i, j});
    }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return std::tie(a.cost, a.row, a.column) < std::tie(b.cost, b.row, b.column);
  });
  Assignment result;
  result.columnOfRow.assign(cost.rows(), -1);
  result.rowOfColumn.assign(cost.cols(), -1);
  for (const Pair& p : pairs) {
    if (result.columnOfRow[p.row] >= 0 || result.rowOfColumn[p.column] >= 0) continue;
    result.columnOfRow[p.row] = p.column;
    result.rowOfColumn[p.column] = p.row;
    result.cost += p.cost;
  }
  return result;
}

}  // namespace bcassim
