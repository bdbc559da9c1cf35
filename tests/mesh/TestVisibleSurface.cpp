// What a camera sees of a surface: the faces most turned to it, until the coverage asked, with
// points uniform by area on them.
#include <gtest/gtest.h>

#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/VisibleSurface.h"

namespace bcassim {
namespace {

// The visible part of a unit sphere seen along +z: the faces most turned to the camera until
// the coverage, i.e. a cap around the pole; the samples lie on it, uniformly by area.
TEST(VisibleSurface, SamplesTheFacesTurnedToTheCameraUpToTheCoverage) {
  const TriMesh sphere = makeIcosphereSurface(1.0, 4);
  const SurfaceSamples s = sampleVisibleSurface(sphere, Vec3::UnitZ(), 0.3, 4000, 7);
  ASSERT_EQ(s.points.rows(), 4000);
  // Whole faces are taken: the coverage is reached, by at most a few faces' area (1,280 faces).
  EXPECT_GE(s.areaFraction, 0.3);
  EXPECT_LT(s.areaFraction, 0.3 + 5.0 / 1280.0);
  const SurfaceLocator locator(sphere);
  // A cap of area fraction f on a sphere spans z in [1 - 2f, 1]; uniform by area, z is uniform
  // there (Archimedes): mean 1 - f, within 5 standard errors.
  const double f = s.areaFraction, zLow = 1.0 - 2.0 * f;
  double zSum = 0.0;
  for (Eigen::Index i = 0; i < s.points.rows(); ++i) {
    EXPECT_LT(locator.closest(s.points.row(i).transpose()).distance, 1e-12);
    EXPECT_GT(s.points(i, 2), zLow - 0.02);  // the polyhedron's faces straddle the cap's rim
    zSum += s.points(i, 2);
  }
  const double spread = (1.0 - zLow) / std::sqrt(12.0 * 4000.0);
  EXPECT_NEAR(zSum / 4000.0, 1.0 - f, 5.0 * spread + 0.005);
  EXPECT_THROW(sampleVisibleSurface(sphere, Vec3::UnitZ(), 0.0, 10, 1), InputError);
  try {
    sampleVisibleSurface(sphere, Vec3::UnitZ(), 1.5, 10, 1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "surface camera coverage 1.5; expected a fraction of the area in (0, 1]");
  }
}

}  // namespace
}  // namespace bcassim
