// Point location: inside points reproduce themselves, outside points get the nearest tet and the
// right distance, linear fields interpolate exactly.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <random>

#include "bcassim/Error.h"
#include "bcassim/mesh/BarycentricMap.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {
namespace {

Eigen::VectorXd flatten(const Eigen::MatrixX3d& V) {
  Eigen::VectorXd x(3 * V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i) x.segment<3>(3 * i) = V.row(i).transpose();
  return x;
}

TEST(BarycentricMap, InsidePointsReproduceThemselves) {
  const TetMesh m = makeCylinderMesh(0.015, 0.18, 3000);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixX3d points(2000, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    // Strictly inside the inscribed polygon: radius below the ring polygon's inradius.
    Vec3 p;
    do p = Vec3(u(rng), u(rng), 0);
    while (p.norm() > 0.95);
    points.row(i) << 0.015 * p(0), 0.015 * p(1), 0.09 + 0.089 * u(rng);
  }
  const auto mapped = mapPoints(m, points);
  const Eigen::VectorXd x = flatten(m.V);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const MappedPoint& mp = mapped[i];
    ASSERT_TRUE(mp.inside) << i;
    EXPECT_EQ(mp.distance, 0.0);
    EXPECT_NEAR(mp.weights.sum(), 1.0, 1e-12);
    EXPECT_GE(mp.weights.minCoeff(), -1e-10);
    EXPECT_LT((interpolate(mp, m, x) - points.row(i).transpose()).norm(), 1e-12);
    EXPECT_LT((interpolate(mp, m) - points.row(i).transpose()).norm(), 1e-12);
  }
}

TEST(BarycentricMap, LinearFieldIsReproducedUnderDeformation) {
  const TetMesh m = makeBoxMesh(Vec3(0.05, 0.03, 0.02), 5, 3, 2);
  Mat3 A;
  A << 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, 0.0, -0.2, 1.3;
  const Vec3 b(0.01, -0.02, 0.005);
  Eigen::MatrixX3d deformed = (m.V * A.transpose()).rowwise() + b.transpose();
  Eigen::MatrixX3d points(4, 3);
  points << 0.011, 0.012, 0.013, 0.049, 0.001, 0.0199, 0.025, 0.015, 0.01, 0.0, 0.0, 0.0;
  const auto mapped = mapPoints(m, points);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    ASSERT_TRUE(mapped[i].inside);
    const Vec3 want = A * points.row(i).transpose() + b;
    EXPECT_LT((interpolate(mapped[i], m, flatten(deformed)) - want).norm(), 1e-14);
  }
}

TEST(BarycentricMap, OutsidePointsMapToNearestTetWithDistance) {
  const Vec3 size(0.05, 0.03, 0.02);
  const TetMesh m = makeBoxMesh(size, 5, 3, 2);
  Eigen::MatrixX3d points(3, 3);
  points << 0.05 + 0.1, 0.012, 0.007,  // 0.1 m beyond the face x = 0.05
      0.02, 0.01, -0.003,              // 3 mm below the face z = 0
      -0.03, -0.04, 0.01;              // nearest to the edge x = y = 0: distance 5 cm
  const Eigen::MatrixX3d nearest =
      (Eigen::MatrixX3d(3, 3) << 0.05, 0.012, 0.007, 0.02, 0.01, 0.0, 0.0, 0.0, 0.01).finished();
  const double distance[3] = {0.1, 0.003, 0.05};
  const auto mapped = mapPoints(m, points);
  for (int i = 0; i < 3; ++i) {
    const MappedPoint& mp = mapped[i];
    EXPECT_FALSE(mp.inside) << i;
    EXPECT_NEAR(mp.distance, distance[i], 1e-14) << i;
    EXPECT_GE(mp.weights.minCoeff(), 0.0);
    EXPECT_NEAR(mp.weights.sum(), 1.0, 1e-14);
    EXPECT_LT((interpolate(mp, m) - nearest.row(i).transpose()).norm(), 1e-14) << i;
  }
}

TEST(BarycentricMap, BeyondTheEndCapDistanceIsHeightAboveIt) {
  // Above the cap z = L and within its polygon, the nearest mesh point is straight below.
  const TetMesh m = makeCylinderMesh(0.015, 0.18, 915);
  Eigen::MatrixX3d points(50, 3);
  for (int i = 0; i < 50; ++i)
    points.row(i) << 0.005 * std::cos(i), 0.005 * std::sin(i), 0.18 + 0.001 * (i + 1);
  const auto mapped = mapPoints(m, points);
  for (int i = 0; i < 50; ++i) {
    EXPECT_FALSE(mapped[i].inside);
    EXPECT_NEAR(mapped[i].distance, 0.001 * (i + 1), 1e-14);
    const Vec3 onCap = interpolate(mapped[i], m);
    EXPECT_NEAR(onCap(2), 0.18, 1e-15);
    EXPECT_NEAR(onCap(0), points(i, 0), 1e-15);
    EXPECT_NEAR(onCap(1), points(i, 1), 1e-15);
  }
}

TEST(BarycentricMap, RejectsEmptyMeshAndWrongPositionSize) {
  EXPECT_THROW(TetLocator(TetMesh{}), InputError);
  const TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);
  const auto mapped = mapPoints(m, Eigen::MatrixX3d::Constant(1, 3, 0.5));
  EXPECT_THROW(interpolate(mapped[0], m, Eigen::VectorXd::Zero(5)), InputError);
}

TEST(BarycentricMap, MatchesBruteForceOnFineMesh) {
  const TetMesh m = makeCylinderMesh(0.015, 0.18, 11000);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.02, 0.2);
  Eigen::MatrixX3d points(300, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    points.row(i) << 0.1 * u(rng), 0.1 * u(rng), u(rng);
  const auto mapped = mapPoints(TetLocator(m), points);
  const BoundarySurface boundary = extractBoundary(m);
  int inside = 0;
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Vec3 p = points.row(i);
    bool containedSomewhere = false;
    for (Eigen::Index t = 0; t < m.numTets() && !containedSomewhere; ++t) {
      const Vec3 a = m.V.row(m.T(t, 0));
      Mat3 edges;
      edges << Vec3(m.V.row(m.T(t, 1))) - a, Vec3(m.V.row(m.T(t, 2))) - a,
          Vec3(m.V.row(m.T(t, 3))) - a;
      const Vec3 w = edges.inverse() * (p - a);
      containedSomewhere = w.minCoeff() >= -1e-10 && w.sum() <= 1 + 1e-10;
    }
    ASSERT_EQ(mapped[i].inside, containedSomewhere) << i;
    if (mapped[i].inside) {
      ++inside;
      EXPECT_LT((interpolate(mapped[i], m) - p).norm(), 1e-12);
      continue;
    }
    double best = 1e300;
    for (Eigen::Index f = 0; f < boundary.F.rows(); ++f) {
      const Vec3 a = m.V.row(boundary.F(f, 0)), b = m.V.row(boundary.F(f, 1)),
                 c = m.V.row(boundary.F(f, 2));
      const Vec3 w = closestPointOnTriangle(p, a, b, c);
      best = std::min(best, (w(0) * a + w(1) * b + w(2) * c - p).norm());
    }
    EXPECT_NEAR(mapped[i].distance, best, 1e-15) << i;
    EXPECT_NEAR((interpolate(mapped[i], m) - p).norm(), best, 1e-15) << i;
  }
  // The sampling box straddles the cylinder: both branches must have been exercised.
  EXPECT_GT(inside, 0);
  EXPECT_LT(inside, points.rows());
}

}  // namespace
}  // namespace bcassim
