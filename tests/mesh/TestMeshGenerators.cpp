// Generated meshes: exact counts, exact or converging volume, orientation, quality.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/MeshQuality.h"

namespace bcassim {
namespace {

double surfaceArea(const TetMesh& mesh, const BoundarySurface& b) {
  double area = 0;
  for (Eigen::Index f = 0; f < b.F.rows(); ++f) {
    const Vec3 p = mesh.V.row(b.F(f, 0)), q = mesh.V.row(b.F(f, 1)), r = mesh.V.row(b.F(f, 2));
    area += 0.5 * (q - p).cross(r - p).norm();
  }
  return area;
}

TEST(BoxMesh, CountsVolumeAndOrientation) {
  const Vec3 size(0.15, 0.03, 0.03);
  const TetMesh m = makeBoxMesh(size, 7, 3, 4);
  EXPECT_EQ(m.numNodes(), 8 * 4 * 5);
  EXPECT_EQ(m.numTets(), 6 * 7 * 3 * 4);
  const MeshQuality q = measureQuality(m);
  EXPECT_EQ(q.numInverted, 0);
  EXPECT_GT(q.minVolume, 0.0);
  EXPECT_NEAR(q.totalVolume, size.prod(), 1e-12 * size.prod());
  EXPECT_EQ(q.bboxMin, Vec3::Zero());
  EXPECT_EQ(q.bboxMax, size);  // far faces exact, not rounded
  // Every Kuhn tet of a hex has the same volume, 1/6 of it.
  EXPECT_NEAR(q.minVolume, q.maxVolume, 1e-12 * q.maxVolume);
}

TEST(BoxMesh, KuhnSplitOfACubeHasKnownDihedralAngles) {
  const MeshQuality q = measureQuality(makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1));
  EXPECT_NEAR(q.minDihedralDeg, 45.0, 1e-9);
  EXPECT_NEAR(q.maxDihedralDeg, 90.0, 1e-9);
}

TEST(BoxMesh, NodeNumberingIsDocumentedLayout) {
  const TetMesh m = makeBoxMesh(Vec3(3, 2, 1), 3, 2, 1);
  const int i = 2, j = 1, k = 1;
  EXPECT_EQ(m.V.row(i + 4 * (j + 3 * k)), Eigen::RowVector3d(2, 1, 1));
}

TEST(BoxMesh, RejectsBadArguments) {
  EXPECT_THROW(makeBoxMesh(Vec3(1, 0, 1), 1, 1, 1), InputError);
  EXPECT_THROW(makeBoxMesh(Vec3(1, 1, 1), 1, 0, 1), InputError);
  EXPECT_THROW(makeBoxMeshWithTargetTets(Vec3(1, 1, 1), 0), InputError);
}

TEST(BoxMesh, TargetTetsNearTargetWithCubicCells) {
  struct Case {
    Vec3 size;
    int target;
  };
  for (const Case& c : {Case{Vec3(0.15, 0.03, 0.03), 26000}, Case{Vec3(0.10, 0.15, 0.01), 420},
                        Case{Vec3(0.05, 0.05, 0.05), 6000}}) {
    const TetMesh m = makeBoxMeshWithTargetTets(c.size, c.target);
    EXPECT_NEAR(double(m.numTets()), c.target, 0.01 * c.target);
    // Cells are near-cubic: hex sides within a factor 1.5, an axis with a single cell aside.
    Vec3 h;
    Eigen::Vector3i n;
    for (int a = 0; a < 3; ++a) {
      std::vector<double> coords(m.V.col(a).data(), m.V.col(a).data() + m.numNodes());
      std::sort(coords.begin(), coords.end());
      n(a) = static_cast<int>(std::unique(coords.begin(), coords.end()) - coords.begin()) - 1;
      h(a) = c.size(a) / n(a);
    }
    EXPECT_EQ(m.numTets(), 6 * n.prod());
    double hMin = 1e300;
    for (int a = 0; a < 3; ++a)
      if (n(a) > 1) hMin = std::min(hMin, h(a));
    EXPECT_LE(h.maxCoeff() / hMin, 1.5);
    const MeshQuality q = measureQuality(m);
    EXPECT_EQ(q.numInverted, 0);
    EXPECT_NEAR(q.totalVolume, c.size.prod(), 1e-12 * c.size.prod());
  }
}

TEST(BoxMesh, BoundaryIsClosedWithBoxAreaAndOutwardNormals) {
  const Vec3 size(0.10, 0.15, 0.01);
  const TetMesh m = makeBoxMesh(size, 7, 10, 1);
  const BoundarySurface b = extractBoundary(m);
  EXPECT_NEAR(surfaceArea(m, b), 2 * (size(0) * size(1) + size(1) * size(2) + size(0) * size(2)),
              1e-12);
  // Each of the 6 sides carries 2 triangles per grid cell of that side.
  EXPECT_EQ(b.F.rows(), 4 * (7 * 10 + 10 * 1 + 7 * 1));
  const Vec3 centre = size / 2;
  for (Eigen::Index f = 0; f < b.F.rows(); ++f) {
    const Vec3 faceCentre =
        (m.V.row(b.F(f, 0)) + m.V.row(b.F(f, 1)) + m.V.row(b.F(f, 2))).transpose() / 3;
    const Vec3 n = b.faceNormals.row(f);
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    EXPECT_GT(n.dot(faceCentre - centre), 0.0) << "face " << f;
    // Box faces are axis-aligned: the normal is a signed unit axis.
    EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0, 1e-12);
  }
  for (int v : b.nodes)
    EXPECT_GT(Vec3(b.vertexNormals.row(v)).dot(m.V.row(v).transpose() - centre), 0);
}

TEST(CylinderMesh, ThesisTargetsWithinTenPercentAndWellShaped) {
  const double r = 0.015, length = 0.18;
  for (int target : {915, 11000}) {
    const TetMesh m = makeCylinderMesh(r, length, target);
    EXPECT_NEAR(double(m.numNodes()), target, 0.10 * target);
    const MeshQuality q = measureQuality(m);
    EXPECT_EQ(q.numInverted, 0);
    EXPECT_GT(q.minVolume, 0.0);
    // Achieved by the ring construction: 33.1 deg at 915 nodes, 35.4 deg at 11,000.
    EXPECT_GE(q.minDihedralDeg, 33.0) << target;
    EXPECT_LE(q.maxDihedralDeg, 130.0) << target;
    EXPECT_NEAR(q.bboxMin(2), 0.0, 0.0);
    EXPECT_NEAR(q.bboxMax(2), length, 0.0);
    EXPECT_NEAR(q.bboxMax(0), r, 1e-15);  // a node of every ring sits at angle 0
    EXPECT_NEAR(m.V.leftCols<2>().rowwise().norm().maxCoeff(), r, 1e-15);
  }
}

TEST(CylinderMesh, ExactNodeCountsOfTheThesisMeshes) {
  // Pinned so that a change of the construction is noticed: scenes refer to these meshes.
  EXPECT_EQ(makeCylinderMesh(0.015, 0.18, 915).numNodes(), 930);
  EXPECT_EQ(makeCylinderMesh(0.015, 0.18, 11000).numNodes(), 11100);
}

TEST(CylinderMesh, VolumeAndAreaConvergeUnderRefinement) {
  const double r = 0.015, length = 0.18;
  const double volume = std::numbers::pi * r * r * length;
  const double area = 2 * std::numbers::pi * r * length + 2 * std::numbers::pi * r * r;
  double lastVolumeError = 1e300, lastAreaError = 1e300;
  for (int target : {300, 915, 3000, 11000}) {
    const TetMesh m = makeCylinderMesh(r, length, target);
    const double volumeError = std::abs(measureQuality(m).totalVolume - volume) / volume;
    const double areaError = std::abs(surfaceArea(m, extractBoundary(m)) - area) / area;
    EXPECT_LT(volumeError, lastVolumeError) << target;
    EXPECT_LT(areaError, lastAreaError) << target;
    lastVolumeError = volumeError;
    lastAreaError = areaError;
  }
  EXPECT_LT(lastVolumeError, 0.005);
  EXPECT_LT(lastAreaError, 0.005);
}

TEST(CylinderMesh, IsDeterministicAndConforming) {
  const TetMesh a = makeCylinderMesh(0.015, 0.18, 915), b = makeCylinderMesh(0.015, 0.18, 915);
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.T, b.T);
  // Conforming and watertight: the boundary is a closed 2-manifold of genus 0, so
  // V - E + F = 2 with every edge in exactly two faces.
  const BoundarySurface s = extractBoundary(a);
  std::map<std::pair<int, int>, int> edges;
  for (Eigen::Index f = 0; f < s.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int p = s.F(f, c), q = s.F(f, (c + 1) % 3);
      ++edges[{std::min(p, q), std::max(p, q)}];
    }
  for (const auto& [e, count] : edges) EXPECT_EQ(count, 2);
  EXPECT_EQ(Eigen::Index(s.nodes.size()) - Eigen::Index(edges.size()) + s.F.rows(), 2);
}

TEST(CylinderMesh, RejectsBadArguments) {
  EXPECT_THROW(makeCylinderMesh(0.0, 0.18, 915), InputError);
  EXPECT_THROW(makeCylinderMesh(0.015, -1.0, 915), InputError);
  EXPECT_THROW(makeCylinderMesh(0.015, 0.18, 3), InputError);
}

}  // namespace
}  // namespace bcassim
