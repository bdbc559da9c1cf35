// validateTetMesh: exact messages for each defect, orientation normalisation.
#include <fmt/format.h>
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

TEST(MeshValidation, TetListingANodeTwice) {
  TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);
  m.T(2, 3) = m.T(2, 0);
  EXPECT_EQ(
      messageOf(m, "liver.vtk"),
      fmt::format("liver.vtk: tet 2 lists node {} twice; expected 4 distinct nodes", m.T(2, 0)));
}

// Two tets on one base, the second with its apex in the base plane.
TetMesh flatSecondTet() {
  TetMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.3, 0.3, 0;
  m.T.resize(2, 4);
  m.T << 0, 1, 2, 3, 0, 1, 2, 4;
  return m;
}

TEST(MeshValidation, DegenerateTet) {
  EXPECT_EQ(messageOf(flatSecondTet(), "flat.vtk"),
            "flat.vtk: tet 1 is degenerate (volume 0 m^3); expected a non-flat tetrahedron");
}

TEST(MeshValidation, SameTetTwice) {
  TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);
  m.T.conservativeResize(7, 4);
  m.T.row(6) << m.T(4, 2), m.T(4, 0), m.T(4, 3), m.T(4, 1);  // tet 4's nodes, reordered
  m.region = Eigen::VectorXi::Zero(7);
  EXPECT_EQ(messageOf(m, "liver.vtk"),
            "liver.vtk: tet 6 has the same 4 nodes as tet 4; expected each tetrahedron once");
}

TEST(MeshValidation, UnusedNode) {
  TetMesh m = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);
  m.V.conservativeResize(9, 3);
  m.V.row(8) << 2, 2, 2;
  EXPECT_EQ(messageOf(m, "liver.vtk"),
            "liver.vtk: node 8 belongs to no tetrahedron; expected every node in one (remove "
            "unused nodes from the file)");
}

// With the file's numbering and lines, messages name items as the file does: a Gmsh file whose
// nodes are tagged 10, 11, ... on lines 5, 6, ... and whose elements are tagged 100, 101 on lines
// 20, 21.
TEST(MeshValidation, MessagesUseTheFileNumbersAndLines) {
  MeshOrigin origin;
  origin.source = "liver.msh";
  origin.nodeNumbers = {10, 11, 12, 13, 14};
  origin.nodeLines = {5, 6, 7, 8, 9};
  origin.tetWord = "element";
  origin.tetNumbers = {100, 101};
  origin.tetLines = {20, 21};
  const auto messageWithOrigin = [&](TetMesh mesh) {
    try {
      validateTetMesh(mesh, origin);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(messageWithOrigin(flatSecondTet()),
            "liver.msh:21: element 101 is degenerate (volume 0 m^3); expected a non-flat "
            "tetrahedron");
  TetMesh twice = flatSecondTet();
  twice.T.row(1) << 3, 2, 1, 0;
  EXPECT_EQ(messageWithOrigin(twice),
            "liver.msh:21: element 101 has the same 4 nodes as element 100 (line 20); expected "
            "each tetrahedron once");
  TetMesh unused = flatSecondTet();
  unused.T.conservativeResize(1, 4);  // node 4 (tag 14) is left in no tet
  EXPECT_EQ(messageWithOrigin(unused),
            "liver.msh:9: node 14 belongs to no tetrahedron; expected every node in one (remove "
            "unused nodes from the file)");
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
