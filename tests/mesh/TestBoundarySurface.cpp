// Boundary extraction: closed, outward, consistent with its tets; the compact TriMesh copy.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <map>

#include "bcassim/Error.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {
namespace {

TEST(BoundarySurface, BoxSurfaceIsClosedGenusZero) {
  const TetMesh m = makeBoxMesh(Vec3(0.03, 0.02, 0.01), 3, 2, 2);
  const BoundarySurface s = extractBoundary(m);
  std::map<std::pair<int, int>, int> edges;
  for (Eigen::Index f = 0; f < s.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int p = s.F(f, c), q = s.F(f, (c + 1) % 3);
      ++edges[{std::min(p, q), std::max(p, q)}];
    }
  for (const auto& [e, count] : edges) EXPECT_EQ(count, 2) << e.first << "-" << e.second;
  const Eigen::Index euler = Eigen::Index(s.nodes.size()) - Eigen::Index(edges.size()) + s.F.rows();
  EXPECT_EQ(euler, 2);
  // Only the interior nodes of a 4x3x3 node grid are off the surface: (4-2)*(3-2)*(3-2) = 2.
  EXPECT_EQ(Eigen::Index(s.nodes.size()), m.numNodes() - 2);
  EXPECT_TRUE(std::is_sorted(s.nodes.begin(), s.nodes.end()));
}

TEST(BoundarySurface, FacesBelongToTheirTetAndFaceAwayFromIt) {
  const TetMesh m = makeBoxMesh(Vec3(0.03, 0.02, 0.01), 3, 2, 2);
  const BoundarySurface s = extractBoundary(m);
  for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
    const int t = s.faceTet(f);
    int opposite = -1, shared = 0;
    for (int k = 0; k < 4; ++k) {
      const bool onFace = (s.F.row(f).array() == m.T(t, k)).any();
      shared += onFace;
      if (!onFace) opposite = m.T(t, k);
    }
    ASSERT_EQ(shared, 3);
    const Vec3 a = m.V.row(s.F(f, 0));
    EXPECT_LT(Vec3(s.faceNormals.row(f)).dot(Vec3(m.V.row(opposite)) - a), 0.0);
  }
}

TEST(BoundarySurface, InteriorNodesHaveZeroNormal) {
  const TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 2, 2, 2);
  const BoundarySurface s = extractBoundary(m);
  const int centre = 1 + 3 * (1 + 3 * 1);
  EXPECT_EQ(Vec3(s.vertexNormals.row(centre)), Vec3::Zero());
  // A corner's area-weighted normal points diagonally outward; at (0,0,0) the three sides carry
  // unequal triangle fans, so only the signs are certain.
  EXPECT_TRUE((s.vertexNormals.row(0).array() < 0).all());
  EXPECT_NEAR(s.vertexNormals.row(0).norm(), 1.0, 1e-12);
}

TEST(BoundarySurface, TriMeshIsCompactAndMapsBack) {
  const TetMesh m = makeBoxMesh(Vec3(0.03, 0.02, 0.01), 3, 2, 2);
  const BoundarySurface s = extractBoundary(m);
  const TriMesh tri = toTriMesh(m, s);
  ASSERT_EQ(tri.V.rows(), Eigen::Index(s.nodes.size()));
  ASSERT_EQ(tri.F.rows(), s.F.rows());
  EXPECT_GE(tri.F.minCoeff(), 0);
  EXPECT_LT(tri.F.maxCoeff(), tri.V.rows());
  for (Eigen::Index f = 0; f < tri.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(s.nodes[tri.F(f, c)], s.F(f, c));
      EXPECT_EQ(tri.V.row(tri.F(f, c)), m.V.row(s.F(f, c)));
    }
}

TEST(BoundarySurface, SingleTetIsItsOwnBoundary) {
  TetMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.T.resize(1, 4);
  m.T << 0, 1, 2, 3;
  const BoundarySurface s = extractBoundary(m);
  ASSERT_EQ(s.F.rows(), 4);
  // Face 3 is opposite node 3 (0,0,1): the bottom, facing -z.
  EXPECT_EQ(Vec3(s.faceNormals.row(3)), Vec3(0, 0, -1));
  EXPECT_EQ(s.F.row(3), Eigen::RowVector3i(0, 2, 1));
}

TEST(BoundarySurface, FaceSharedByThreeTetsIsRejected) {
  TetMesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0.2, 0.2, 1;
  m.T.resize(3, 4);
  m.T << 0, 1, 2, 3, 0, 2, 1, 4, 0, 1, 2, 5;
  try {
    extractBoundary(m);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "boundary extraction: face (0, 1, 2) is shared by 3 tets; expected at most 2");
  }
}

}  // namespace
}  // namespace bcassim
