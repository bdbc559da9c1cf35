// PointCloudObservation (a partial surface seen as unlabelled points): the closest points it
// fixes at the mean are those of a brute-force search over every triangle, far points are dropped
// by the robust cutoff, and a forecast is observed through the faces and weights fixed at the mean.
#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <utility>

#include "bcassim/Error.h"
#include "bcassim/coupling/PointCloudObservation.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {
namespace {

struct Deformed {
  Eigen::MatrixX3i F;
  Eigen::VectorXd x;  // node positions, 3 per node, m
  Eigen::Index nodes = 0;
};

// A 4 x 3 x 2 cm box, bent and twisted smoothly so that its faces are not axis-aligned.
Deformed bentBox() {
  const TetMesh mesh = makeBoxMesh(Vec3(0.04, 0.03, 0.02), 4, 3, 2);
  Deformed d;
  d.F = extractBoundary(mesh).F;
  d.nodes = mesh.numNodes();
  d.x.resize(3 * d.nodes);
  for (Eigen::Index n = 0; n < d.nodes; ++n) {
    const Vec3 p = mesh.V.row(n).transpose();
    d.x.segment<3>(3 * n) = p + Vec3(0.002 * p.z() / 0.02, 0.001 * std::sin(60 * p.x()),
                                     0.003 * (p.x() / 0.04) * (p.x() / 0.04));
  }
  return d;
}

Observation cloudOf(const std::vector<Vec3>& points, double sigma) {
  Eigen::VectorXd values(3 * static_cast<Eigen::Index>(points.size()));
  for (size_t i = 0; i < points.size(); ++i)
    values.segment<3>(3 * static_cast<Eigen::Index>(i)) = points[i];
  return Observation::withSigma(values, sigma);
}

// Closest point of the deformed surface to p by trying every triangle.
Vec3 bruteForceClosest(const Deformed& d, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  Vec3 closest = Vec3::Zero();
  for (Eigen::Index f = 0; f < d.F.rows(); ++f) {
    const Vec3 a = d.x.segment<3>(3 * d.F(f, 0)), b = d.x.segment<3>(3 * d.F(f, 1)),
               c = d.x.segment<3>(3 * d.F(f, 2));
    const Vec3 w = closestPointOnTriangle(p, a, b, c);
    const Vec3 q = w(0) * a + w(1) * b + w(2) * c;
    if ((q - p).norm() < best) {
      best = (q - p).norm();
      closest = q;
    }
  }
  return closest;
}

TEST(PointCloudObservation, ClosestPointsAtTheMeanAreThoseOfABruteForceSearch) {
  const Deformed d = bentBox();
  PointCloudSettings settings;
  settings.residual = CloudResidual::Point;
  settings.distanceFactor = 1e6;  // keep every point
  settings.minPoints = 1;
  PointCloudObservation op(d.F, d.nodes, settings);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.01, 0.05);
  std::vector<Vec3> points;
  for (int i = 0; i < 200; ++i) points.emplace_back(u(rng), u(rng) * 0.8, u(rng) * 0.6);
  const Observation used = op.linearize(d.x, cloudOf(points, 1e-3));
  EXPECT_EQ(op.lastStats().points, 200);
  EXPECT_EQ(op.lastStats().used, 200);
  Eigen::VectorXd predicted;
  op.predict(d.x, predicted);
  ASSERT_EQ(predicted.size(), 600);
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3 expected = bruteForceClosest(d, points[i]);
    const Vec3 got = predicted.segment<3>(3 * static_cast<Eigen::Index>(i));
    // The same distance (ties between faces may pick another, equally close point).
    EXPECT_NEAR((got - points[i]).norm(), (expected - points[i]).norm(), 1e-12) << "point " << i;
  }
  EXPECT_EQ(used.values, cloudOf(points, 1e-3).values);
}

TEST(PointCloudObservation, AForecastIsObservedThroughTheFacesFixedAtTheMean) {
  const Deformed d = bentBox();
  PointCloudSettings settings;
  settings.minPoints = 1;
  settings.minCutoff = 1.0;
  PointCloudObservation op(d.F, d.nodes, settings);  // residual: normal
  const std::vector<Vec3> points = {Vec3(0.02, 0.015, 0.03), Vec3(0.05, 0.01, 0.01),
                                    Vec3(0.01, -0.01, 0.012)};
  const Observation used = op.linearize(d.x, cloudOf(points, 2e-3));
  ASSERT_EQ(used.values.size(), 3);
  Eigen::VectorXd atMean, shifted;
  op.predict(d.x, atMean);
  // A rigid translation of the forecast moves each prediction by the translation along its normal.
  const Vec3 shift(0.001, -0.002, 0.0005);
  Eigen::VectorXd moved = d.x;
  for (Eigen::Index n = 0; n < d.nodes; ++n) moved.segment<3>(3 * n) += shift;
  op.predict(moved, shifted);
  for (Eigen::Index i = 0; i < 3; ++i) {
    const Vec3 p = points[static_cast<size_t>(i)];
    const Vec3 q = bruteForceClosest(d, p);
    const Vec3 normal = (p - q).normalized();  // outside the box: along the face normal (±)
    EXPECT_NEAR(std::abs(used.values(i) - atMean(i)), (p - q).norm(), 1e-12) << i;
    EXPECT_NEAR(std::abs(shifted(i) - atMean(i)), std::abs(normal.dot(shift)), 1e-12) << i;
    EXPECT_DOUBLE_EQ(used.variance(i), 4e-6);
  }
}

TEST(PointCloudObservation, PointsBeyondTheRobustCutoffAreDroppedForTheStep) {
  const Deformed d = bentBox();
  PointCloudSettings settings;  // k = 3, floor 5 mm, at least 10 points
  settings.minCutoff = 0.001;
  PointCloudObservation op(d.F, d.nodes, settings);
  // 12 points 1 mm above the top face's middle, one 20 mm above it.
  std::vector<Vec3> points;
  for (int i = 0; i < 12; ++i) {
    const Vec3 onTop = bruteForceClosest(d, Vec3(0.01 + 0.0015 * i, 0.015, 0.05));
    points.push_back(onTop + Vec3(0, 0, 0.001));
  }
  points.push_back(bruteForceClosest(d, Vec3(0.02, 0.015, 0.05)) + Vec3(0, 0, 0.02));
  const Observation used = op.linearize(d.x, cloudOf(points, 1e-3));
  EXPECT_EQ(op.lastStats().points, 13);
  EXPECT_EQ(op.lastStats().used, 12);
  ASSERT_EQ(used.present.size(), 13u);
  EXPECT_FALSE(used.present[12]);
  EXPECT_NEAR(op.lastStats().cutoff, 3 * op.lastStats().medianDistance, 1e-15);
  EXPECT_LT(op.lastStats().medianDistance, 0.0011);

  // Fewer usable points than min_points: nothing is used, the step is a prediction.
  settings.minPoints = 13;
  PointCloudObservation strict(d.F, d.nodes, settings);
  const Observation none = strict.linearize(d.x, cloudOf(points, 1e-3));
  EXPECT_EQ(strict.lastStats().used, 0);
  for (bool present : none.present) EXPECT_FALSE(present);
}

// A background as large as the organ's part of the view (a table 1.5 cm under it, 12 points
// among 24): the median then lies in the gap, and the robust cutoff keeps the table. Only the
// closest half counted (keep_fraction 0.5), or nothing beyond 1 cm (max_distance), the organ's
// points alone are used.
TEST(PointCloudObservation, ABackgroundAsLargeAsTheOrganIsLeftOutByKeepFractionOrMaxDistance) {
  const Deformed d = bentBox();
  std::vector<Vec3> points;
  for (int i = 0; i < 12; ++i) {
    const Vec3 onTop = bruteForceClosest(d, Vec3(0.01 + 0.0015 * i, 0.015, 0.05));
    points.push_back(onTop + Vec3(0, 0, 0.0005 * (i % 3)));
  }
  for (int i = 0; i < 12; ++i)
    points.push_back(bruteForceClosest(d, Vec3(0.005 + 0.0025 * i, 0.012, 0.05)) +
                     Vec3(0, 0, 0.015 + 0.001 * (i % 2)));
  const auto usedOf = [&](const PointCloudSettings& settings, PointCloudStepStats& stats) {
    PointCloudObservation op(d.F, d.nodes, settings);
    const Observation used = op.linearize(d.x, cloudOf(points, 1e-3));
    stats = op.lastStats();
    int organ = 0, background = 0;
    for (size_t i = 0; i < points.size(); ++i)
      if (used.present[i]) ++(i < 12 ? organ : background);
    return std::pair{organ, background};
  };
  PointCloudStepStats stats;
  PointCloudSettings settings;                              // k = 3, floor 5 mm
  EXPECT_EQ(usedOf(settings, stats), (std::pair{12, 12}));  // the median in the gap
  settings.keepFraction = 0.5;
  EXPECT_EQ(usedOf(settings, stats), (std::pair{12, 0}));
  EXPECT_LT(stats.medianDistance, 0.0011);
  EXPECT_LT(stats.cutoff, 0.0011);  // the last of the closest half
  settings.keepFraction = 1.0;
  settings.maxCutoff = 0.01;
  EXPECT_EQ(usedOf(settings, stats), (std::pair{12, 0}));
  EXPECT_EQ(stats.cutoff, 0.01);
}

TEST(PointCloudObservation, RejectsATriangleOutsideTheMesh) {
  Eigen::MatrixX3i F(1, 3);
  F << 0, 1, 7;
  try {
    PointCloudObservation op(F, 5, PointCloudSettings{});
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "point cloud: an observed triangle names node 7; the mesh has 5 nodes");
  }
}

}  // namespace
}  // namespace bcassim
