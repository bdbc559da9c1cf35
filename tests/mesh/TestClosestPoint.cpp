// Closest point on a triangle surface: the locator agrees with brute force over all faces.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "bcassim/Error.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {
namespace {

TEST(ClosestPointOnTriangle, EachVoronoiRegion) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_LT((closestPointOnTriangle(Vec3(0.2, 0.3, 5), a, b, c) - Vec3(0.5, 0.2, 0.3)).norm(),
            1e-15);
  EXPECT_EQ(closestPointOnTriangle(Vec3(-1, -1, 1), a, b, c), Vec3(1, 0, 0));
  EXPECT_EQ(closestPointOnTriangle(Vec3(2, -1, 0), a, b, c), Vec3(0, 1, 0));
  EXPECT_EQ(closestPointOnTriangle(Vec3(-1, 3, 0), a, b, c), Vec3(0, 0, 1));
  EXPECT_EQ(closestPointOnTriangle(Vec3(0.25, -2, 0), a, b, c), Vec3(0.75, 0.25, 0));
  EXPECT_EQ(closestPointOnTriangle(Vec3(-2, 0.5, 0), a, b, c), Vec3(0.5, 0, 0.5));
  EXPECT_EQ(closestPointOnTriangle(Vec3(1, 1, -3), a, b, c), Vec3(0, 0.5, 0.5));
}

TEST(ClosestPointOnTriangle, DegenerateTriangleGivesAPointOnIt) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);
  const Vec3 w = closestPointOnTriangle(Vec3(1.5, 1, 0), a, b, c);
  EXPECT_NEAR(w.sum(), 1.0, 1e-15);
  EXPECT_GE(w.minCoeff(), 0.0);
  EXPECT_NEAR((w(0) * a + w(1) * b + w(2) * c - Vec3(1.5, 0, 0)).norm(), 0.0, 1e-15);
}

// The distance from p to the surface, face by face.
double bruteForceDistance(const TriMesh& surface, const Vec3& p) {
  double best = 1e300;
  for (Eigen::Index f = 0; f < surface.F.rows(); ++f) {
    const Vec3 a = surface.V.row(surface.F(f, 0)), b = surface.V.row(surface.F(f, 1)),
               c = surface.V.row(surface.F(f, 2));
    const Vec3 w = closestPointOnTriangle(p, a, b, c);
    best = std::min(best, (w(0) * a + w(1) * b + w(2) * c - p).norm());
  }
  return best;
}

TEST(SurfaceLocator, MatchesBruteForceOnRandomQueries) {
  const TetMesh tets = makeCylinderMesh(0.015, 0.18, 3000);
  const TriMesh surface = toTriMesh(tets, extractBoundary(tets));
  const SurfaceLocator locator(surface);
  ASSERT_EQ(locator.numFaces(), surface.F.rows());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> xy(-0.03, 0.03), z(-0.05, 0.23);
  for (int q = 0; q < 500; ++q) {
    const Vec3 p(xy(rng), xy(rng), z(rng));
    const double best = bruteForceDistance(surface, p);
    const SurfacePoint s = locator.closest(p);
    EXPECT_NEAR(s.distance, best, 1e-15) << q;
    EXPECT_NEAR((s.point - p).norm(), s.distance, 1e-15);
    EXPECT_NEAR(s.barycentric.sum(), 1.0, 1e-12);
    EXPECT_GE(s.barycentric.minCoeff(), 0.0);
    const Vec3 fromFace = s.barycentric(0) * surface.V.row(surface.F(s.face, 0)).transpose() +
                          s.barycentric(1) * surface.V.row(surface.F(s.face, 1)).transpose() +
                          s.barycentric(2) * surface.V.row(surface.F(s.face, 2)).transpose();
    EXPECT_LT((fromFace - s.point).norm(), 1e-15);
  }
}

// Built on the rest shape, refitted to a bent and twisted one (several radii of motion): the
// closest points are still exact, and the same as a locator built on the deformed surface.
TEST(SurfaceLocator, RefittedToADeformedSurfaceMatchesBruteForce) {
  const TetMesh tets = makeCylinderMesh(0.015, 0.18, 3000);
  TriMesh surface = toTriMesh(tets, extractBoundary(tets));
  SurfaceLocator locator(surface);
  for (Eigen::Index v = 0; v < surface.V.rows(); ++v) {
    const double z = surface.V(v, 2), turn = 4.0 * z;  // rad: a 41 degree twist over the length
    const double x = surface.V(v, 0), y = surface.V(v, 1);
    surface.V.row(v) << std::cos(turn) * x - std::sin(turn) * y + 0.3 * z * z,
        std::sin(turn) * x + std::cos(turn) * y, z;
  }
  locator.refit(surface);
  const SurfaceLocator rebuilt(surface);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> xy(-0.03, 0.03), z(-0.05, 0.23);
  for (int q = 0; q < 300; ++q) {
    const Vec3 p(xy(rng) + 0.005, xy(rng), z(rng));
    const double best = bruteForceDistance(surface, p);
    const SurfacePoint s = locator.closest(p);
    EXPECT_NEAR(s.distance, best, 1e-15) << q;
    EXPECT_NEAR(rebuilt.closest(p).distance, s.distance, 1e-15) << q;
  }
  TriMesh fewer = surface;
  fewer.F.conservativeResize(surface.F.rows() - 1, 3);
  try {
    locator.refit(fewer);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "surface locator: refit with " + std::to_string(fewer.F.rows()) +
                  " faces; it was built with " + std::to_string(surface.F.rows()));
  }
}

TEST(SurfaceLocator, OneOffQueryAndBadInput) {
  TriMesh tri;
  tri.V.resize(3, 3);
  tri.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  tri.F.resize(1, 3);
  tri.F << 0, 1, 2;
  const SurfacePoint s = closestPointOnSurface(tri, Vec3(0.25, 0.25, -0.5));
  EXPECT_EQ(s.face, 0);
  EXPECT_EQ(s.point, Vec3(0.25, 0.25, 0));
  EXPECT_EQ(s.distance, 0.5);
  tri.F(0, 2) = 3;
  try {
    SurfaceLocator{tri};
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "surface locator: face 0 refers to vertex 3; expected an index in [0, 3)");
  }
  EXPECT_THROW(SurfaceLocator{TriMesh{}}, InputError);
}

}  // namespace
}  // namespace bcassim
