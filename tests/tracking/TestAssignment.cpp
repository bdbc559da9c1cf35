// Optimal assignment against brute force over every matching, the greedy baseline's known
// weakness, and the gated pairing of tracks with detections.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>

#include "bcassim/Error.h"
#include "bcassim/tracking/Assignment.h"
#include "bcassim/tracking/GatedMatching.h"
#include "bcassim/tracking/GreedyAssignment.h"

namespace bcassim {
namespace {

constexpr double kForbidden = std::numeric_limits<double>::infinity();

struct Best {
  int pairs = -1;
  double cost = 0.0;
};

// Every injective map of the smaller side into the larger one: the most allowed pairs, then the
// least cost.
Best bruteForce(const Eigen::MatrixXd& cost) {
  const bool transposed = cost.rows() > cost.cols();
  const Eigen::MatrixXd c = transposed ? Eigen::MatrixXd(cost.transpose()) : cost;
  std::vector<int> columns(c.cols());
  std::iota(columns.begin(), columns.end(), 0);
  Best best;
  do {
    int pairs = 0;
    double sum = 0.0;
    for (int i = 0; i < c.rows(); ++i)
      if (c(i, columns[i]) != kForbidden) {
        ++pairs;
        sum += c(i, columns[i]);
      }
    if (pairs > best.pairs || (pairs == best.pairs && sum < best.cost)) best = {pairs, sum};
  } while (std::next_permutation(columns.begin(), columns.end()));
  return best;
}

// The assignment is a matching of allowed pairs and its cost is their sum.
void expectConsistent(const Eigen::MatrixXd& cost, const Assignment& a) {
  ASSERT_EQ(a.columnOfRow.size(), static_cast<size_t>(cost.rows()));
  ASSERT_EQ(a.rowOfColumn.size(), static_cast<size_t>(cost.cols()));
  double sum = 0.0;
  for (int i = 0; i < cost.rows(); ++i) {
    const int j = a.columnOfRow[i];
    if (j < 0) continue;
    EXPECT_EQ(a.rowOfColumn[j], i);
    EXPECT_NE(cost(i, j), kForbidden) << "forbidden pair (" << i << ", " << j << ") used";
    sum += cost(i, j);
  }
  for (int j = 0; j < cost.cols(); ++j) {
    if (a.rowOfColumn[j] >= 0) {
      EXPECT_EQ(a.columnOfRow[a.rowOfColumn[j]], j);
    }
  }
  EXPECT_NEAR(a.cost, sum, 1e-12 * (1.0 + std::abs(sum)));
}

TEST(OptimalAssignment, EqualsBruteForceOnRandomRectangularMatrices) {
  std::mt19937 rng(2024);
  std::uniform_int_distribution<int> size(1, 7);
  std::uniform_real_distribution<double> value(-5.0, 10.0), unit(0.0, 1.0);
  int withForbidden = 0, rectangular = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int rows = size(rng), cols = size(rng);
    const double forbiddenShare = trial % 3 == 0 ? 0.0 : 0.5 * unit(rng);
    Eigen::MatrixXd cost(rows, cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) {
        // Integer costs half the time, so that ties between matchings occur.
        const double v = trial % 2 ? value(rng) : std::floor(value(rng));
        cost(i, j) = unit(rng) < forbiddenShare ? kForbidden : v;
      }
    withForbidden += (cost.array() == kForbidden).any();
    rectangular += rows != cols;
    const Assignment a = solveOptimalAssignment(cost);
    expectConsistent(cost, a);
    const Best best = bruteForce(cost);
    ASSERT_EQ(a.numPairs(), best.pairs) << "trial " << trial << "\n" << cost;
    ASSERT_NEAR(a.cost, best.cost, 1e-9) << "trial " << trial << "\n" << cost;
  }
  EXPECT_GT(withForbidden, 200);
  EXPECT_GT(rectangular, 300);
}

TEST(OptimalAssignment, ForbiddenPairsAndEdgeShapes) {
  // Row 0 may only take column 1, which row 1 prefers: the maximum matching pairs both anyway.
  Eigen::MatrixXd cost(2, 2);
  cost << kForbidden, 5.0, 1.0, 0.0;
  Assignment a = solveOptimalAssignment(cost);
  EXPECT_EQ(a.columnOfRow, (std::vector<int>{1, 0}));
  EXPECT_EQ(a.cost, 6.0);
  // Everything forbidden, and empty matrices: no pairs.
  a = solveOptimalAssignment(Eigen::MatrixXd::Constant(2, 3, kForbidden));
  EXPECT_EQ(a.numPairs(), 0);
  EXPECT_EQ(a.rowOfColumn, (std::vector<int>{-1, -1, -1}));
  EXPECT_EQ(solveOptimalAssignment(Eigen::MatrixXd(0, 4)).rowOfColumn.size(), 4u);
  EXPECT_EQ(solveOptimalAssignment(Eigen::MatrixXd(3, 0)).columnOfRow,
            (std::vector<int>{-1, -1, -1}));
  // A column nobody may take.
  cost.resize(2, 3);
  cost << 1.0, kForbidden, 3.0, 2.0, kForbidden, 1.0;
  a = solveOptimalAssignment(cost);
  EXPECT_EQ(a.columnOfRow, (std::vector<int>{0, 2}));
  EXPECT_EQ(a.rowOfColumn[1], -1);
}

TEST(OptimalAssignment, NanOrMinusInfinityIsAnInputError) {
  Eigen::MatrixXd cost = Eigen::MatrixXd::Zero(2, 3);
  cost(1, 2) = std::nan("");
  try {
    solveOptimalAssignment(cost);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "assignment: cost (1, 2) is nan; expected a finite number or +infinity for a "
                 "forbidden pair");
  }
  cost(1, 2) = -kForbidden;
  EXPECT_THROW(solveGreedyAssignment(cost), InputError);
}

TEST(GreedyAssignment, TakesTheSmallestFirstAndCanBeBeaten) {
  // Greedy takes (0, 0) = 1 first and is left with (1, 1) = 10; the optimum crosses: 2 + 2.
  Eigen::MatrixXd cost(2, 2);
  cost << 1.0, 2.0, 2.0, 10.0;
  const Assignment g = solveGreedyAssignment(cost);
  EXPECT_EQ(g.columnOfRow, (std::vector<int>{0, 1}));
  EXPECT_EQ(g.cost, 11.0);
  EXPECT_EQ(solveOptimalAssignment(cost).cost, 4.0);
  // Random matrices: greedy is a maximal matching and never cheaper than the optimum when it
  // makes as many pairs.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::MatrixXd c(5, 6);
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 6; ++j) c(i, j) = value(rng) < 0.3 ? kForbidden : value(rng);
    const Assignment greedy = solveGreedyAssignment(c), optimal = solveOptimalAssignment(c);
    expectConsistent(c, greedy);
    for (int i = 0; i < 5; ++i) {
      for (int j = 0; j < 6; ++j) {
        if (c(i, j) != kForbidden) {
          EXPECT_TRUE(greedy.columnOfRow[i] >= 0 || greedy.rowOfColumn[j] >= 0);
        }
      }
    }
    EXPECT_LE(greedy.numPairs(), optimal.numPairs());
    if (greedy.numPairs() == optimal.numPairs()) {
      EXPECT_GE(greedy.cost, optimal.cost - 1e-12);
    }
  }
}

TEST(GatedMatching, PairsOnlyWithinTheGateAndWhenCheaperThanLeavingBoth) {
  const double gate = 0.01;
  // Track 0 is 4 mm from detection 0; track 1 is 12 mm from it (beyond the gate) and 9 mm from
  // detection 1.
  Eigen::MatrixXd d2(2, 2);
  d2 << 0.004 * 0.004, 0.02 * 0.02, 0.012 * 0.012, 0.009 * 0.009;
  for (const AssignmentMethod m : {AssignmentMethod::Optimal, AssignmentMethod::Greedy}) {
    const Assignment a = matchWithinGate(d2, gate, m);
    EXPECT_EQ(a.columnOfRow, (std::vector<int>{0, 1}));
  }
  // Two tracks 6 mm and 7 mm from one detection, the second also 8 mm from another: pairing
  // 6 + 8 mm (100 mm^2) is cheaper than 7 mm plus one unpaired track and detection
  // (49 + 100 mm^2), so the optimum pairs both; greedy takes 6 mm first as well.
  d2.resize(2, 2);
  d2 << 36e-6, kForbidden, 49e-6, 64e-6;
  EXPECT_EQ(matchWithinGate(d2, gate, AssignmentMethod::Optimal).columnOfRow,
            (std::vector<int>{0, 1}));
  // Where they differ: greedy pairs track 0 with detection 1 (1 mm) and is left with track 1 and
  // detection 0 (9 mm): 82 mm^2; the optimum pairs 5 mm and 5 mm: 50 mm^2.
  d2 << 25e-6, 1e-6, 81e-6, 25e-6;
  EXPECT_EQ(matchWithinGate(d2, gate, AssignmentMethod::Greedy).columnOfRow,
            (std::vector<int>{1, 0}));
  EXPECT_EQ(matchWithinGate(d2, gate, AssignmentMethod::Optimal).columnOfRow,
            (std::vector<int>{0, 1}));
  try {
    matchWithinGate(d2, 0.0, AssignmentMethod::Optimal);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "gate 0 m; expected a positive finite distance (m)");
  }
}

}  // namespace
}  // namespace bcassim
