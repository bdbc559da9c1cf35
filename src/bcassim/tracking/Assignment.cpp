#include "bcassim/tracking/Assignment.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bcassim/Error.h"

namespace bcassim {

int Assignment::numPairs() const {
  return static_cast<int>(std::count_if(columnOfRow.begin(), columnOfRow.end(),
                                        [](int column) { return column >= 0; }));
}

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Hungarian method by shortest augmenting paths with row and column potentials, for a matrix
// with rows <= columns and every entry finite: rows are added one at a time, each by a
// Dijkstra-like search over reduced costs. Returns the column of each row.
std::vector<int> assignAllRows(const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows()), m = static_cast<int>(a.cols());
  // 1-based as in the classical statement; column 0 is the virtual start of each search.
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0), minReduced(m + 1);
  std::vector<int> rowOf(m + 1, 0), previousColumn(m + 1, 0);
  std::vector<char> visited(m + 1);
  for (int i = 1; i <= n; ++i) {
    rowOf[0] = i;
    int j0 = 0;
    std::fill(minReduced.begin(), minReduced.end(), kInfinity);
    std::fill(visited.begin(), visited.end(), 0);
    do {
      visited[j0] = 1;
      const int i0 = rowOf[j0];
      double delta = kInfinity;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (visited[j]) continue;
        const double reduced = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (reduced < minReduced[j]) {
          minReduced[j] = reduced;
          previousColumn[j] = j0;
        }
        if (minReduced[j] < delta) {
          delta = minReduced[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (visited[j]) {
          u[rowOf[j]] += delta;
          v[j] -= delta;
        } else {
          minReduced[j] -= delta;
        }
      }
      j0 = j1;
    } while (rowOf[j0] != 0);
    do {  // augment along the path back to the start
      const int j1 = previousColumn[j0];
      rowOf[j0] = rowOf[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> columnOf(n, -1);
  for (int j = 1; j <= m; ++j)
    if (rowOf[j] > 0) columnOf[rowOf[j] - 1] = j - 1;
  return columnOf;
}

}  // namespace

void requireAssignmentCosts(const Eigen::MatrixXd& cost) {
  for (Eigen::Index j = 0; j < cost.cols(); ++j)
    for (Eigen::Index i = 0; i < cost.rows(); ++i)
      if (std::isnan(cost(i, j)) || cost(i, j) == -kInfinity)
        throw InputError(
            fmt::format("assignment: cost ({}, {}) is {}; expected a finite number "
                        "or +infinity for a forbidden pair",
                        i, j, cost(i, j)));
}

Assignment solveOptimalAssignment(const Eigen::MatrixXd& cost) {
  requireAssignmentCosts(cost);
  const Eigen::Index rows = cost.rows(), cols = cost.cols();
  double largestMagnitude = 0.0;
  bool anyAllowed = false;
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) {
      const double c = cost(i, j);
      if (c == kInfinity) continue;
      anyAllowed = true;
      largestMagnitude = std::max(largestMagnitude, std::abs(c));
    }
  Assignment result;
  result.columnOfRow.assign(rows, -1);
  result.rowOfColumn.assign(cols, -1);
  if (!anyAllowed) return result;
  // A forbidden pair costs more than any difference between sums of at most min(rows, cols)
  // finite costs, so using one fewer forbidden pair always wins: the matching with the most
  // allowed pairs is found first, the cheapest among those second.
  const Eigen::Index n = std::min(rows, cols);
  const double forbiddenCost =
      largestMagnitude > 0.0 ? 2.0 * static_cast<double>(n + 1) * largestMagnitude : 1.0;
  const bool transposed = rows > cols;
  Eigen::MatrixXd finite = transposed ? Eigen::MatrixXd(cost.transpose()) : cost;
  finite = finite.unaryExpr([&](double c) { return c == kInfinity ? forbiddenCost : c; });
  const std::vector<int> columnOf = assignAllRows(finite);
  for (int k = 0; k < static_cast<int>(columnOf.size()); ++k) {
    const int i = transposed ? columnOf[k] : k;
    const int j = transposed ? k : columnOf[k];
    if (cost(i, j) == kInfinity) continue;
    result.columnOfRow[i] = j;
    result.rowOfColumn[j] = i;
    result.cost += cost(i, j);
  }
  return result;
}

}  // namespace bcassim
