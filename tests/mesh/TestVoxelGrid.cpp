// Voxel-grid thinning (mesh/VoxelGrid): centroids per occupied cube in first-seen order, the cap
// on the count met by the finest grid of the sequence that meets it, every point near a centroid.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "bcassim/mesh/VoxelGrid.h"

namespace bcassim {
namespace {

TEST(VoxelGrid, CentroidsOfTheOccupiedCubesInFirstSeenOrder) {
  Eigen::MatrixX3d P(5, 3);
  P << 0.25, 0.25, 0.25,  // cube (0, 0, 0)
      1.5, 0.5, 0.5,      // cube (1, 0, 0)
      0.75, 0.75, 0.75,   // cube (0, 0, 0)
      -0.5, 0.5, 0.5,     // cube (-1, 0, 0): floor, not truncation
      1.5, 0.5, 0.75;     // cube (1, 0, 0)
  const Eigen::MatrixX3d C = voxelGridCentroids(P, 1.0);
  Eigen::MatrixX3d expected(3, 3);
  expected << 0.5, 0.5, 0.5, 1.5, 0.5, 0.625, -0.5, 0.5, 0.5;
  EXPECT_EQ(C, expected);
  EXPECT_THROW(voxelGridCentroids(P, 0.0), std::invalid_argument);
}

// 20,000 points on a 10 cm x 10 cm patch of a sphere (an RGB-D view of an organ), in metres.
Eigen::MatrixX3d densePatch() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  Eigen::MatrixX3d P(20000, 3);
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const double x = u(rng), y = u(rng);
    P.row(i) << x, y, 0.2 - std::sqrt(0.04 - x * x - y * y);
  }
  return P;
}

TEST(VoxelGrid, ThinningMeetsTheCapWithTheFinestGridThatDoes) {
  const Eigen::MatrixX3d P = densePatch();
  const ThinnedPoints t = thinToAtMost(P, 2000);
  ASSERT_GT(t.voxel, 0.0);
  EXPECT_LE(t.points.rows(), 2000);
  // The grid one step finer (1.25 times) would have kept too many: the cap is met, not overshot.
  EXPECT_GT(voxelGridCentroids(P, t.voxel / 1.25).rows(), 2000);
  EXPECT_GT(t.points.rows(), 2000 / 1.25 / 1.25 / 2);
  // Every point lies within a cube's diagonal of some centroid: the patch is covered evenly.
  for (Eigen::Index i = 0; i < P.rows(); i += 97)
    EXPECT_LE((t.points.rowwise() - P.row(i)).rowwise().norm().minCoeff(),
              std::sqrt(3.0) * t.voxel);
  // Under the cap and without a voxel edge: the points as they are.
  const ThinnedPoints kept = thinToAtMost(P.topRows(500), 2000);
  EXPECT_EQ(kept.voxel, 0.0);
  EXPECT_EQ(kept.points, P.topRows(500));
  // A given edge is applied whatever the count, and grown only where the cap needs it.
  const ThinnedPoints fixed = thinToAtMost(P.topRows(500), 2000, 0.004);
  EXPECT_EQ(fixed.voxel, 0.004);
  EXPECT_EQ(fixed.points, voxelGridCentroids(P.topRows(500), 0.004));
  EXPECT_LE(thinToAtMost(P, 100, 0.001).points.rows(), 100);
  // All points at one place: one centroid.
  const Eigen::MatrixX3d same = Eigen::MatrixX3d::Constant(50, 3, 0.1);
  EXPECT_EQ(thinToAtMost(same, 10).points.rows(), 1);
}

}  // namespace
}  // namespace bcassim
