// Quality report on meshes whose figures are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/MeshQuality.h"

namespace bcassim {
namespace {

TEST(MeshQuality, RegularTetrahedron) {
  TetMesh m;
  m.V.resize(4, 3);
  m.V << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  m.T.resize(1, 4);
  m.T << 0, 1, 2, 3;
  if (MeshQuality q = measureQuality(m); q.totalVolume < 0) m.T.row(0) << 0, 1, 3, 2;
  const MeshQuality q = measureQuality(m);
  const double dihedral = std::acos(1.0 / 3.0) * 180 / std::numbers::pi;  // 70.53 deg
  EXPECT_NEAR(q.minDihedralDeg, dihedral, 1e-12);
  EXPECT_NEAR(q.maxDihedralDeg, dihedral, 1e-12);
  EXPECT_NEAR(q.totalVolume, 8.0 / 3.0, 1e-14);  // cube of side 2 minus 4 corners of 4/3
  EXPECT_EQ(q.numInverted, 0);
  EXPECT_EQ(q.bboxMin, Vec3(-1, -1, -1));
  EXPECT_EQ(q.bboxMax, Vec3(1, 1, 1));
}

TEST(MeshQuality, CountsInvertedTets) {
  TetMesh m = makeBoxMesh(Vec3(1, 2, 3), 2, 1, 1);
  m.T.row(0).tail<2>().reverseInPlace();
  m.T.row(7).tail<2>().reverseInPlace();
  const MeshQuality q = measureQuality(m);
  EXPECT_EQ(q.numNodes, 12);
  EXPECT_EQ(q.numTets, 12);
  EXPECT_EQ(q.numInverted, 2);
  EXPECT_NEAR(q.minVolume, -0.5, 1e-14);
  EXPECT_NEAR(q.maxVolume, 0.5, 1e-14);
  EXPECT_NEAR(q.totalVolume, 6.0 - 4 * 0.5, 1e-13);
}

}  // namespace
}  // namespace bcassim
