// Tests of ligament spring extrusion (flat and curved surfaces), grouping, and the vessel region.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/io/ObjFormat.h"
#include "bcassim/ligaments/AttachmentCurve.h"
#include "bcassim/ligaments/EsegLabels.h"
#include "bcassim/ligaments/LigamentSprings.h"
#include "bcassim/ligaments/SurfaceMesher.h"
#include "bcassim/ligaments/VesselRegion.h"
#include "bcassim/mesh/BarycentricMap.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "ligaments/LigamentTestData.h"
#include "support/SharedData.h"

namespace bcassim {
namespace {

double angle(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

void expectOnBoundary(const TetMesh& mesh, const LigamentSprings& lig, double tolerance) {
  const BoundarySurface boundary = extractBoundary(mesh);
  const SurfaceLocator surface(toTriMesh(mesh, boundary));
  const auto& springs = lig.springs.springs();
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(
      Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>(mesh.V).data(),
      3 * mesh.numNodes());
  for (size_t s = 0; s < springs.size(); ++s) {
    const Vec3 p = lig.springs.attachment(mesh, x, s);
    EXPECT_LT((p - lig.attachments.row(s).transpose()).norm(), 1e-9) << s;
    EXPECT_LT(surface.closest(p).distance, tolerance) << s;
  }
}

TEST(LigamentSprings, FlatFaceSpringsAreNormalAndRestLong) {
  const TetMesh box = makeBoxMesh(Vec3(0.1, 0.1, 0.1), 10, 10, 10);
  Eigen::MatrixX3d curve(3, 3);  // across the top face z = 0.1
  curve << 0.02, 0.05, 0.1, 0.05, 0.05, 0.1, 0.08, 0.05, 0.1;
  LigamentOptions options;
  options.spacing = 0.005;
  options.numGroups = 3;
  const LigamentSprings lig = buildLigamentSprings(box, curve, options);
  const auto& springs = lig.springs.springs();
  ASSERT_EQ(springs.size(), 2u * 12u);  // 2 rows of round(0.06 / 0.005) samples
  EXPECT_NEAR(lig.curveLength, 0.06, 1e-12);
  EXPECT_EQ(lig.springs.numGroups(), 3);
  for (size_t s = 0; s < springs.size(); ++s) {
    const Vec3 a = lig.attachments.row(s).transpose();
    EXPECT_NEAR((springs[s].anchor - a).norm(), 0.03, 1e-12);
    EXPECT_DOUBLE_EQ(springs[s].restLength, 0.03);
    EXPECT_LT(angle(springs[s].anchor - a, Vec3::UnitZ()), 1e-6);
    EXPECT_NEAR(a.z(), 0.1, 1e-12);
    EXPECT_NEAR(std::abs(a.y() - 0.05), 0.004, 1e-12);  // the two rows at +-layerOffset
  }
  expectOnBoundary(box, lig, 1e-12);
  // Groups: contiguous arcs of equal length (4 samples each), same split in both rows.
  for (size_t s = 0; s < springs.size(); ++s) {
    EXPECT_EQ(springs[s].group, static_cast<int>((s % 12) / 4)) << s;
  }
}

TEST(LigamentSprings, CurvedSurfaceSpringsFollowNormals) {
  SurfaceMeshingOptions meshing;
  meshing.scale = 1.0;
  meshing.targetNodes = 600;
  const double r = 0.05;
  const TetMesh ball = meshSurface(test::makeIcosphere(r, 3), meshing).mesh;
  // A quarter great circle from +x to +y.
  const int m = 40;
  Eigen::MatrixX3d curve(m + 1, 3);
  for (int i = 0; i <= m; ++i) {
    const double t = 0.5 * M_PI * i / m;
    curve.row(i) << r * std::cos(t), r * std::sin(t), 0;
  }
  LigamentOptions options;
  options.numGroups = 5;
  options.coefficients.kGamma = 10;
  const LigamentSprings lig = buildLigamentSprings(ball, curve, options);
  const auto& springs = lig.springs.springs();
  ASSERT_GE(springs.size(), 2u * 5u);
  double maxAngle = 0;
  for (size_t s = 0; s < springs.size(); ++s) {
    const Vec3 a = lig.attachments.row(s).transpose();
    EXPECT_NEAR((springs[s].anchor - a).norm(), 0.03, 1e-12);
    maxAngle = std::max(maxAngle, angle(springs[s].anchor - a, a));
  }
  EXPECT_LT(maxAngle, 5.0 * M_PI / 180);  // faceted sphere: vertex normals close to radial
  expectOnBoundary(ball, lig, 1e-9);
  EXPECT_LT(lig.maxSnapDistance, 0.005);
  // Groups are contiguous and near equal in arc length along each row.
  const size_t perRow = springs.size() / 2;
  std::vector<int> counts(5, 0);
  for (size_t s = 0; s < perRow; ++s) {
    if (s > 0) {
      EXPECT_GE(springs[s].group, springs[s - 1].group);
    }
    EXPECT_EQ(springs[s].group, springs[s + perRow].group);
    ++counts[springs[s].group];
  }
  for (int c : counts) EXPECT_NEAR(c, perRow / 5.0, 1.0);
  EXPECT_DOUBLE_EQ(lig.springs.coefficients(4).kGamma, 10);
}

TEST(LigamentSprings, ABandPutsTheTwoLayersOnItsEdges) {
  const TetMesh box = makeBoxMesh(Vec3(0.1, 0.1, 0.1), 10, 10, 10);
  // Across the top face z = 0.1; the band widens from +-2 mm to +-12 mm along it, its edges given
  // above the face (an atlas' band is snapped too).
  Eigen::MatrixX3d curve(3, 3), lower(3, 3), upper(3, 3);
  curve << 0.02, 0.05, 0.1, 0.05, 0.05, 0.1, 0.08, 0.05, 0.1;
  lower << 0.02, 0.048, 0.101, 0.05, 0.043, 0.101, 0.08, 0.038, 0.101;
  upper << 0.02, 0.052, 0.101, 0.05, 0.057, 0.101, 0.08, 0.062, 0.101;
  LigamentOptions options;
  options.spacing = 0.005;
  options.numGroups = 3;
  const LigamentSprings plain = buildLigamentSprings(box, curve, options);
  options.bandLower = lower;
  options.bandUpper = upper;
  const LigamentSprings lig = buildLigamentSprings(box, curve, options);
  const auto& springs = lig.springs.springs();
  ASSERT_EQ(springs.size(), plain.springs.springs().size());
  const size_t perRow = springs.size() / 2;
  for (size_t s = 0; s < springs.size(); ++s) {
    const Vec3 a = lig.attachments.row(s).transpose();
    // The half width at the sample's arc length: 2 mm + 10 mm x (x - 0.02) / 0.06.
    const double half = 0.002 + 0.01 * (a.x() - 0.02) / 0.06;
    EXPECT_NEAR(a.y(), s < perRow ? 0.05 - half : 0.05 + half, 1e-12) << s;
    EXPECT_NEAR(a.x(), plain.attachments(static_cast<Eigen::Index>(s), 0), 1e-12) << s;
    EXPECT_NEAR(a.z(), 0.1, 1e-12);
    EXPECT_EQ(springs[s].group, plain.springs.springs()[s].group) << s;
    EXPECT_LT(angle(springs[s].anchor - a, Vec3::UnitZ()), 1e-6);
  }
  EXPECT_NEAR(lig.maxSnapDistance, 0.001, 1e-12);
  expectOnBoundary(box, lig, 1e-12);
}

TEST(LigamentSprings, BadInputIsAnInputError) {
  const TetMesh box = makeBoxMesh(Vec3(0.1, 0.1, 0.1), 2, 2, 2);
  EXPECT_THROW(buildLigamentSprings(box, Eigen::MatrixX3d::Zero(1, 3)), InputError);
  EXPECT_THROW(buildLigamentSprings(box, Eigen::MatrixX3d::Zero(2, 3)), InputError);
  LigamentOptions bad;
  bad.layers = 3;
  EXPECT_THROW(buildLigamentSprings(box, Eigen::MatrixX3d::Identity(2, 3), bad), InputError);
  LigamentOptions band;
  band.bandLower = band.bandUpper = Eigen::MatrixX3d::Identity(3, 3);
  try {
    buildLigamentSprings(box, Eigen::MatrixX3d::Identity(2, 3), band);
    ADD_FAILURE() << "a band of 3 points for a curve of 2 was taken";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "ligament: a band of 3 lower and 3 upper points with 2 layer(s) for a curve of 2 "
                 "points; expected as many points on each edge as the curve has, and 2 layers");
  }
  band.bandLower = band.bandUpper = Eigen::MatrixX3d::Identity(2, 3);
  band.layers = 1;
  EXPECT_THROW(buildLigamentSprings(box, Eigen::MatrixX3d::Identity(2, 3), band), InputError);
}

TEST(VesselRegion, BallAroundGuessedHilum) {
  const TetMesh box = makeBoxMesh(Vec3(0.1, 0.1, 0.1), 4, 4, 4);
  Eigen::MatrixX3d curve(2, 3);  // ligament on the anterior (y = 0) top edge
  curve << 0, 0, 0.1, 0.1, 0, 0.1;
  const Vec3 hilum = guessHilumPoint(box, curve, Vec3::UnitY());
  EXPECT_NEAR(hilum.y(), 0.1, 1e-12);  // posterior face
  EXPECT_NEAR(hilum.z(), 0.0, 1e-12);  // farthest from the ligament
  const std::vector<int> nodes = nodesWithinRadius(box, hilum, 0.026);
  EXPECT_FALSE(nodes.empty());
  for (int n : nodes) EXPECT_LE((box.V.row(n).transpose() - hilum).norm(), 0.026);
}

}  // namespace
}  // namespace bcassim

namespace bcassim {
namespace {

TEST(LigamentSprings, FalciformSpringsOnCtLiver) {
  SHARED_FILE_OR_SKIP(obj, "livers/LiTS-0.obj");
  SHARED_FILE_OR_SKIP(eseg, "livers/LiTS-0.eseg");
  const TriMesh liver = readObj(obj);
  const AttachmentCurve curve =
      extractAttachmentCurve(liver, readEseg(eseg, liver), 2, "LiTS-0.eseg");
  EXPECT_GT(curve.length, 50.0);  // mm: the falciform attachment spans several centimetres
  SurfaceMeshingOptions meshing;
  meshing.targetNodes = 800;
  const TetMesh mesh = meshSurface(liver, meshing, "LiTS-0.obj").mesh;
  const LigamentSprings lig = buildLigamentSprings(mesh, 1e-3 * curve.points);
  EXPECT_NEAR(lig.curveLength, 1e-3 * curve.length, 1e-12);
  EXPECT_LT(lig.maxSnapDistance, 0.005);  // the curve lies on the CT surface, Mesh_3 within mm
  EXPECT_EQ(lig.springs.numGroups(), 4);
  for (const CubicSpring& s : lig.springs.springs()) {
    EXPECT_GE(s.tet, 0);
    EXPECT_NEAR(s.weights.sum(), 1.0, 1e-9);
  }
}

}  // namespace
}  // namespace bcassim
