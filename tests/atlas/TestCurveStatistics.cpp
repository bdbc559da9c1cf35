// Plane intersections, per-plane curve statistics and the curve atlas on a template, checked on
// curves whose crossings are known in closed form.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "atlas/AtlasTestMeshes.h"
#include "bcassim/Error.h"
#include "bcassim/atlas/CurveAtlas.h"
#include "bcassim/atlas/CurveStatistics.h"
#include "bcassim/atlas/CuttingPlanes.h"
#include "bcassim/atlas/PlaneIntersection.h"

namespace bcassim {
namespace {

constexpr double kPi = std::numbers::pi;

// Great half-circle of radius R in the plane x = 0 (angles t from -limit to limit measured from
// +y towards +z), rotated by phi about the z axis.
Eigen::MatrixX3d rotatedArc(double R, double phi, double limit, int n) {
  Eigen::MatrixX3d c(n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = -limit + 2.0 * limit * i / (n - 1);
    c.row(i) << -R * std::cos(t) * std::sin(phi), R * std::cos(t) * std::cos(phi), R * std::sin(t);
  }
  return c;
}

TEST(PlaneIntersection, KnownPolylineCrossings) {
  // A zig-zag in the x-z plane crossing z = 0.5 on three segments and touching it at a vertex.
  Eigen::MatrixX3d p(5, 3);
  p << 0, 0, 0,   //
      1, 0, 1,    //
      2, 0, 0,    //
      3, 0, 0.5,  // on the plane
      4, 0, 1;
  const CuttingPlaneFamily f = parallelPlanes({0, 0, 0}, {0, 0, 2}, {0.5});
  const std::vector<PlaneHit> hits = intersectPolyline(p, f.planes[0]);
  ASSERT_EQ(hits.size(), 3u);
  EXPECT_NEAR((hits[0].point - Eigen::Vector3d(0.5, 0, 0.5)).norm(), 0.0, 1e-15);
  EXPECT_NEAR(hits[0].position, 0.5, 1e-15);
  EXPECT_NEAR((hits[1].point - Eigen::Vector3d(1.5, 0, 0.5)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((hits[2].point - Eigen::Vector3d(3, 0, 0.5)).norm(), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(hits[2].position, 3.0);
  // A plane the polyline never reaches.
  EXPECT_TRUE(intersectPolyline(p, parallelPlanes({0, 0, 0}, {0, 0, 1}, {2.0}).planes[0]).empty());
}

TEST(PlaneIntersection, RadialHalfPlaneKeepsItsSideOnly) {
  // A full circle around the x axis crosses the plane y = 0 twice; the half-plane at angle
  // pi/2 (towards +z) keeps only the top crossing.
  const int n = 73;
  Eigen::MatrixX3d c(n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * kPi * (i + 0.5) / (n - 1);
    c.row(i) << 0.3, 2.0 * std::cos(t), 2.0 * std::sin(t);
  }
  const CuttingPlaneFamily f = radialPlanes({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {kPi / 2, -kPi / 2});
  const auto top = intersectPolyline(c, f.planes[0]);
  const auto bottom = intersectPolyline(c, f.planes[1]);
  ASSERT_EQ(top.size(), 1u);
  ASSERT_EQ(bottom.size(), 1u);
  EXPECT_NEAR(top[0].point.y(), 0.0, 1e-12);
  EXPECT_GT(top[0].point.z(), 1.9);  // chord of a 5-degree polygon: within 2 (1 - cos 2.5deg)
  EXPECT_LT(bottom[0].point.z(), -1.9);
  EXPECT_NEAR(top[0].point.x(), 0.3, 1e-15);
}

TEST(CurveStatistics, RotatedArcsGiveKnownMeanAndSigma) {
  const double R = 0.08, phi = 0.3;
  // Two arcs rotated by +-phi about z, and the unrotated one, so that the mean lies in x = 0.
  const std::vector<Eigen::MatrixX3d> curves = {
      rotatedArc(R, phi, 1.2, 2001), rotatedArc(R, -phi, 1.2, 2001), rotatedArc(R, 0.0, 1.2, 2001)};
  const std::vector<double> angles = evenAngles(-1.0, 1.0, 9);
  const CuttingPlaneFamily f = radialPlanes({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, angles);
  const std::vector<PlaneStatistics> s = curveStatistics(curves, f);
  ASSERT_EQ(s.size(), angles.size());
  for (size_t k = 0; k < s.size(); ++k) {
    // Crossing of the arc rotated by phi with the half-plane at angle theta: tan t = cos(phi)
    // tan(theta), point R (-cos t sin phi, cos t cos phi, sin t).
    auto crossing = [&](double ph) {
      const double t = std::atan(std::cos(ph) * std::tan(angles[k]));
      return Eigen::Vector3d(-R * std::cos(t) * std::sin(ph), R * std::cos(t) * std::cos(ph),
                             R * std::sin(t));
    };
    const Eigen::Vector3d a = crossing(phi), b = crossing(-phi), c = crossing(0.0);
    const Eigen::Vector3d mean = (a + b + c) / 3.0;
    const double sigma = std::sqrt(
        ((a - mean).squaredNorm() + (b - mean).squaredNorm() + (c - mean).squaredNorm()) / 3.0);
    EXPECT_EQ(s[k].count, 3);
    // Chords of 2000 segments: crossings within R (1 - cos(dt/2)) ~ 3e-8 m of the arc.
    EXPECT_NEAR((s[k].mean - mean).norm(), 0.0, 1e-7) << "plane " << k;
    EXPECT_NEAR(s[k].sigma, sigma, 1e-7) << "plane " << k;
    // The spread is along x (the rotation moves the crossings sideways).
    EXPECT_NEAR(std::abs(s[k].spread.x()), 1.0, 1e-6);
  }
  // At theta = 0 the closed forms are simple: mean R (0, (1 + 2 cos phi)/3, 0).
  EXPECT_NEAR(s[4].mean.y(), R * (1.0 + 2.0 * std::cos(phi)) / 3.0, 1e-7);
}

TEST(CurveStatistics, MedianIgnoresAnOutlierCurve) {
  // Three coincident arcs and one rotated far away: the geometric median of each plane's four
  // crossings is the common crossing, the mean is pulled a quarter of the way to the outlier.
  const double R = 0.08;
  const Eigen::MatrixX3d a = rotatedArc(R, 0.0, 1.0, 401), out = rotatedArc(R, 0.6, 1.0, 401);
  const std::vector<Eigen::MatrixX3d> curves = {a, a, a, out};
  const CuttingPlaneFamily f = radialPlanes({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.5, 0.0, 0.5});
  const auto mean = curveStatistics(curves, f);
  const auto median = curveStatistics(curves, f, CurveCentre::Median);
  for (size_t k = 0; k < 3; ++k) {
    const Eigen::Vector3d common = curveStatistics({a}, f)[k].mean;
    const Eigen::Vector3d outlier = curveStatistics({out}, f)[k].mean;
    EXPECT_NEAR((median[k].mean - common).norm(), 0.0, 1e-12);
    EXPECT_NEAR((mean[k].mean - (3.0 * common + outlier) / 4.0).norm(), 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(median[k].sigma, mean[k].sigma);  // sigma stays about the mean
  }
}

TEST(CurveStatistics, HampelIdentifierRejectsFarPointsOnly) {
  // Points on a line, median 0 (9 points): distances 0, 1, 1, 2, 2, 2.5, 2.5, 40, 0.5; their
  // median is 2, the robust sigma 1.4826 * 2 = 2.97. k = 3 keeps all but 40 (8.9 limit); k = 0.8
  // (2.37) rejects the points at 2.5 as well.
  std::vector<Eigen::Vector3d> p;
  for (double x : {0.0, 1.0, -1.0, 2.0, -2.0, 2.5, -2.5, 40.0, -0.5}) p.emplace_back(x, 0.0, 0.0);
  EXPECT_EQ(hampelInliers(p, 3.0), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 8}));
  EXPECT_EQ(hampelInliers(p, 0.8), (std::vector<int>{0, 1, 2, 3, 4, 8}));
  // Fewer than 3 points: nothing to judge by.
  EXPECT_EQ(hampelInliers({p[0], p[7]}, 3.0), (std::vector<int>{0, 1}));
  EXPECT_THROW(hampelInliers(p, 0.0), InputError);
}

TEST(CurveStatistics, TrimmedMeanIgnoresAnOutlierCurveThatMovesTheMean) {
  // Five arcs fanned by small rotations (the typical curves) and one rotated far away (an
  // atypical annotation or a failed registration). The plain mean is pulled towards the outlier;
  // the trimmed mean is the mean of the five, and so is its sigma.
  const double R = 0.08;
  std::vector<Eigen::MatrixX3d> typical;
  for (double phi : {-0.06, -0.03, 0.0, 0.02, 0.05})
    typical.push_back(rotatedArc(R, phi, 1.0, 401));
  std::vector<Eigen::MatrixX3d> curves = typical;
  curves.push_back(rotatedArc(R, 0.7, 1.0, 401));
  const CuttingPlaneFamily f = radialPlanes({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.5, 0.0, 0.5});
  const auto plain = curveStatistics(curves, f);
  const auto trimmed = curveStatistics(curves, f, CurveCentre::Trimmed);
  const auto inliers = curveStatistics(typical, f);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(trimmed[k].count, 6);
    EXPECT_EQ(trimmed[k].kept, 5);
    EXPECT_EQ(plain[k].kept, 6);
    EXPECT_NEAR((trimmed[k].mean - inliers[k].mean).norm(), 0.0, 1e-14);
    EXPECT_NEAR(trimmed[k].sigma, inliers[k].sigma, 1e-14);
    // The outlier moves the plain mean by about 0.7 R / 6 ~ 9 mm.
    EXPECT_GT((plain[k].mean - inliers[k].mean).norm(), 5e-3);
  }
  // Without an outlier the trimmed mean is the mean.
  const auto clean = curveStatistics(typical, f, CurveCentre::Trimmed);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(clean[k].kept, 5);
    EXPECT_NEAR((clean[k].mean - inliers[k].mean).norm(), 0.0, 1e-14);
  }
  EXPECT_THROW(curveStatistics(curves, f, CurveCentre::Trimmed, -1.0), InputError);
}

TEST(CurveStatistics, PlanesBeyondTheCurvesAreEmpty) {
  const std::vector<Eigen::MatrixX3d> curves = {rotatedArc(0.08, 0.1, 0.5, 101)};
  const CuttingPlaneFamily f = radialPlanes({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.0, 1.0, kPi});
  const auto s = curveStatistics(curves, f);
  EXPECT_EQ(s[0].count, 1);
  EXPECT_EQ(s[0].sigma, 0.0);
  EXPECT_EQ(s[1].count, 0);  // beyond the arc's end at 0.5 rad
  EXPECT_EQ(s[2].count, 0);  // the other side of the axis
}

TEST(CuttingPlanes, RejectDegenerateDirections) {
  EXPECT_THROW(radialPlanes({0, 0, 0}, {0, 0, 0}, {0, 1, 0}, {0.0}), InputError);
  EXPECT_THROW(radialPlanes({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0.0}), InputError);
  EXPECT_THROW(parallelPlanes({0, 0, 0}, {0, 0, 0}, {0.0}), InputError);
}

TEST(CurveAtlas, MeanProjectedOnTemplateAndCarriedByDeformation) {
  const double R = 0.08, phi = 0.25;
  const TriMesh sphere = test::makeIcosphere(R, 4);
  const std::vector<Eigen::MatrixX3d> curves = {rotatedArc(R, phi, 1.0, 801),
                                                rotatedArc(R, -phi, 1.0, 801)};
  const std::vector<double> angles = evenAngles(-0.8, 0.8, 9);
  const CuttingPlaneFamily f = radialPlanes({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, angles);
  const CurveAtlas atlas = buildCurveAtlas(sphere, curves, f, 2);
  ASSERT_EQ(atlas.mean.size(), 9);
  // Level-4 icosphere: faces within R (1 - cos(edge/2)) ~ 3e-4 m... of the sphere.
  const double meshTol = 4e-4;
  const Eigen::MatrixX3d m = atlas.mean.positions(sphere.V);
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    const double theta = angles[atlas.plane[i]];
    // Both crossings have the same y, z (mirror images in x): the mean projects radially onto
    // the sphere in the direction (0, cos theta, sin theta).
    const Eigen::Vector3d expected = R * Eigen::Vector3d(0, std::cos(theta), std::sin(theta));
    EXPECT_NEAR((m.row(i).transpose() - expected).norm(), 0.0, meshTol) << i;
    const double t = std::atan(std::cos(phi) * std::tan(theta));
    EXPECT_NEAR(atlas.sigma(i), R * std::cos(t) * std::sin(phi), 1e-6) << i;
  }
  // The band lies on the surface, on both sides, at about sigma (a chord of the sphere).
  const CarriedCurve same = carryCurve(atlas, sphere.V);
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    EXPECT_NEAR(same.sigma(i), atlas.sigma(i), 0.05 * atlas.sigma(i)) << i;
    EXPECT_LT(same.lower(i, 0), -0.5 * atlas.sigma(i));
    EXPECT_GT(same.upper(i, 0), 0.5 * atlas.sigma(i));
  }
  // Barycentric coordinates are linear: a similarity of the vertices moves everything with it.
  const Eigen::Matrix3d rot =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  const Eigen::RowVector3d shift(0.01, -0.02, 0.03);
  const Eigen::MatrixX3d V2 = ((2.0 * sphere.V) * rot.transpose()).rowwise() + shift;
  const CarriedCurve moved = carryCurve(atlas, V2);
  const Eigen::MatrixX3d expectMean = ((2.0 * same.mean) * rot.transpose()).rowwise() + shift;
  EXPECT_NEAR((moved.mean - expectMean).cwiseAbs().maxCoeff(), 0.0, 1e-14);
  EXPECT_NEAR((moved.sigma - 2.0 * same.sigma).cwiseAbs().maxCoeff(), 0.0, 1e-14);
}

TEST(CurveAtlas, ProjectOntoMovesTheCarriedCurveOntoTheSurface) {
  const double R = 0.08;
  const TriMesh sphere = test::makeIcosphere(R, 4);
  const std::vector<Eigen::MatrixX3d> curves = {rotatedArc(R, 0.2, 1.0, 801),
                                                rotatedArc(R, -0.2, 1.0, 801)};
  const CuttingPlaneFamily f =
      radialPlanes({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, evenAngles(-0.8, 0.8, 9));
  const CurveAtlas atlas = buildCurveAtlas(sphere, curves, f, 2);
  // A deformation that leaves the curve 10 % outside the sphere (a registration that falls short
  // of the patient): projected, it lies on the sphere again, in the same directions.
  const CarriedCurve off = carryCurve(atlas, 1.1 * sphere.V);
  const CarriedCurve on = projectOnto(off, sphere);
  const double meshTol = 4e-4;  // level-4 icosphere faces within R (1 - cos(edge/2)) of the sphere
  for (Eigen::Index i = 0; i < off.mean.rows(); ++i) {
    EXPECT_NEAR(off.mean.row(i).norm(), 1.1 * R, 1.1 * meshTol) << i;
    EXPECT_NEAR(on.mean.row(i).norm(), R, meshTol) << i;
    EXPECT_NEAR(on.lower.row(i).norm(), R, meshTol) << i;
    EXPECT_NEAR(on.upper.row(i).norm(), R, meshTol) << i;
    EXPECT_NEAR(on.mean.row(i).normalized().dot(off.mean.row(i).normalized()), 1.0, 1e-4) << i;
    EXPECT_NEAR(on.sigma(i), off.sigma(i) / 1.1, 0.05 * on.sigma(i)) << i;
  }
  // Points already on the surface stay.
  const CarriedCurve same = carryCurve(atlas, sphere.V);
  EXPECT_LT((projectOnto(same, sphere).mean - same.mean).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(CurveAtlas, RejectsTooFewCrossings) {
  const TriMesh sphere = test::makeIcosphere(0.08, 2);
  const std::vector<Eigen::MatrixX3d> curves = {rotatedArc(0.08, 0.1, 0.5, 101)};
  const CuttingPlaneFamily f = radialPlanes({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.0});
  EXPECT_THROW(buildCurveAtlas(sphere, curves, f, 2), InputError);
}

}  // namespace
}  // namespace bcassim
