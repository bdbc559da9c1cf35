// validateTetMesh: exact messages for each defect, orientation normalisation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "bcassim/Error.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/MeshValidation.h"

namespace bcassim {
namespace {

std::string messageOf(TetMesh mesh, const std::string& source) {
  try {
    validateTetMesh(mesh, source);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MeshValidation, AcceptsGeneratedMeshUnchanged) {
  TetMesh m = makeBoxMesh(Vec3(0.02, 0.01, 0.01), 2, 1, 1);
  const Eigen::MatrixX4i before = m.T;
  validateTetMesh(m, "box");
  EXPECT_EQ(m.T, before);
}

TEST(MeshValidation, NonFiniteCoordinate) {
  TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);
  m.V(3, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(messageOf(m, "liver.vtk"),
            "liver.vtk: node 3 has a non-finite coordinate (nan); expected a finite number in "
            "metres");
}

TEST(MeshValidation, IndexOutOfRange) {
  TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);
  m.T(4, 2) = 8;
  EXPECT_EQ(messageOf(m, "liver.vtk"),
            "liver.vtk: tet 4 refers to node 8; expected an index in [0, 8)");
  m.T(4, 2) = -1;
  EXPECT_EQ(messageOf(m, "liver.vtk"),
            "liver.vtk: tet 4 refers to node -1; expected an index in [0, 8)");
}

TEST(MeshValidation, InvertedTet) {
  TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);  // six tets of volume 1/6 m^3
  m.T.row(5).tail<2>().reverseInPlace();
  EXPECT_EQ(messageOf(m, "liver.vtk"),
            "liver.vtk: tet 5 is inverted (signed volume -0.167 m^3); expected the same "
            "orientation as the other tets");
}

TEST(MeshValidation, DegenerateTet) {
  TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);
  m.T(2, 3) = m.T(2, 0);
  EXPECT_EQ(messageOf(m, "liver.vtk"),
            "liver.vtk: tet 2 is degenerate (volume 0 m^3); expected a non-flat tetrahedron");
}

TEST(MeshValidation, RegionCountMismatch) {
  TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);
  m.region = Eigen::VectorXi::Zero(4);
  EXPECT_EQ(messageOf(m, "liver.vtk"), "liver.vtk: 4 region ids for 6 tets");
}

TEST(MeshValidation, FullyReversedMeshIsFlipped) {
  const TetMesh good = makeBoxMesh(Vec3(0.02, 0.01, 0.01), 2, 1, 1);
  TetMesh m = good;
  m.T.col(0).swap(m.T.col(1));
  for (Eigen::Index t = 0; t < m.numTets(); ++t) ASSERT_LT(signedVolume(m, t), 0);
  validateTetMesh(m, "reversed.vtk");
  for (Eigen::Index t = 0; t < m.numTets(); ++t) {
    EXPECT_NEAR(signedVolume(m, t), signedVolume(good, t), 1e-18);
    // Same node set per tet, only reordered.
    Eigen::Vector4i a = m.T.row(t), b = good.T.row(t);
    std::sort(a.data(), a.data() + 4);
    std::sort(b.data(), b.data() + 4);
    EXPECT_EQ(a, b);
  }
}

TEST(MeshValidation, EmptyMesh) {
  EXPECT_EQ(messageOf(TetMesh{}, "empty.vtk"), "empty.vtk: mesh has no nodes");
}

}  // namespace
}  // namespace bcassim
