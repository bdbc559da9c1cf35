// Consistent nodal shares of a surface traction: exact on faces wholly inside the region, and the
// same continuum load (area, resultant's point) on a coarse and a fine mesh of one cylinder.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bcassim/Error.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/SurfaceTraction.h"

namespace bcassim {
namespace {

double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

// The point where the resultant of the nodal forces acts.
Vec3 loadCentre(const TetMesh& mesh, const SurfaceTractionShares& t) {
  Vec3 c = Vec3::Zero();
  for (size_t k = 0; k < t.nodes.size(); ++k) c += t.shares[k] * mesh.V.row(t.nodes[k]).transpose();
  return c;
}

TEST(SurfaceTraction, HalfOfAFlatFaceIsExact) {
  const TetMesh mesh = makeBoxMesh(Vec3(1, 1, 1), 4, 4, 4);
  // The top face z = 1 for x <= 0.5: the cut runs along mesh lines, so every face is wholly in
  // or out, and the shares integrate the linear function x exactly.
  const auto t = surfaceTractionShares(mesh, BoxRegion{Vec3(-1, -1, 1 - 1e-9), Vec3(0.5, 2, 2)});
  EXPECT_NEAR(t.area, 0.5, 1e-12);
  EXPECT_NEAR(sum(t.shares), 1.0, 1e-12);
  EXPECT_LT((loadCentre(mesh, t) - Vec3(0.25, 0.5, 1.0)).norm(), 1e-12);
  EXPECT_EQ(t.nodes.size(), 3u * 5u);  // x in {0, 0.25, 0.5}, y in 5 values
}

TEST(SurfaceTraction, CurvedPatchIsTheSameLoadOnCoarseAndFineMeshes) {
  // The back of a cylinder (r = 15 mm) where y <= -10 mm, 85 <= z <= 95 mm: the arc where
  // sin(phi) <= -2/3 spans pi - 2 asin(2/3) radians; its centroid is at y = -2 r cos(a) / width.
  const double r = 0.015, alpha = std::asin(2.0 / 3.0), width = std::numbers::pi - 2 * alpha;
  const double area = r * width * 0.01, yc = -2 * r * std::cos(alpha) / width;
  const BoxRegion back{Vec3(-0.02, -0.02, 0.085), Vec3(0.02, -0.01, 0.095)};
  for (int nodes : {915, 11000}) {
    const TetMesh mesh = makeCylinderMesh(r, 0.18, nodes);
    const auto t = surfaceTractionShares(mesh, back);
    EXPECT_NEAR(t.area / area, 1.0, 0.03) << nodes << " nodes";
    EXPECT_NEAR(sum(t.shares), 1.0, 1e-12);
    const Vec3 c = loadCentre(mesh, t);
    EXPECT_NEAR(c.x(), 0.0, 2e-4) << nodes << " nodes";  // m: on the symmetry plane
    EXPECT_NEAR(c.y(), yc, 2e-4) << nodes << " nodes";
    EXPECT_NEAR(c.z(), 0.09, 2e-4) << nodes << " nodes";
  }
}

TEST(SurfaceTraction, SurfacePatchDirectionKeepsOnlyFacingFaces) {
  const TetMesh mesh = makeBoxMesh(Vec3(1, 1, 1), 2, 2, 2);
  // The whole box, but only faces facing +z: the top face.
  SurfacePatchRegion top{BoxRegion{Vec3(-1, -1, -1), Vec3(2, 2, 2)}, Vec3(0, 0, 1), 10.0};
  const auto t = surfaceTractionShares(mesh, top);
  EXPECT_NEAR(t.area, 1.0, 1e-12);
  EXPECT_NEAR(loadCentre(mesh, t).z(), 1.0, 1e-12);
}

TEST(SurfaceTraction, IndexListLoadsTheFacesItLists) {
  const TetMesh mesh = makeBoxMesh(Vec3(1, 1, 1), 2, 2, 2);
  IndexListRegion list;
  for (Eigen::Index n = 0; n < mesh.numNodes(); ++n)
    if (mesh.V(n, 2) == 0.0) list.indices.push_back(static_cast<int>(n));  // bottom face
  const auto t = surfaceTractionShares(mesh, list);
  EXPECT_NEAR(t.area, 1.0, 1e-12);
  EXPECT_LT((loadCentre(mesh, t) - Vec3(0.5, 0.5, 0.0)).norm(), 1e-12);
}

TEST(SurfaceTraction, RegionWithoutSurfaceIsAnError) {
  const TetMesh mesh = makeBoxMesh(Vec3(1, 1, 1), 4, 4, 4);
  try {
    surfaceTractionShares(mesh, SphereRegion{Vec3(0.5, 0.5, 0.5), 0.1});  // inside only
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "the region holds no part of the boundary surface; expected a region that a "
                 "surface load can act on");
  }
}

}  // namespace
}  // namespace bcassim
