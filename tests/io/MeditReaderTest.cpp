// ASCII Medit meshes (.mesh) through readTetMesh: a hand-written file with the sections MMG and
// CGAL write reads to the known cube, a generated box reads as its .vtu does, and every malformed
// case is its exact one-line error naming the line.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <string>

#include "bcassim/io/MeshReader.h"
#include "bcassim/io/MeshWriter.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::TempDir;
using test::writeText;

// `mesh` as Medit text, vertices with round-trip precision, references 0 for the vertices.
std::string meditText(const TetMesh& mesh, const std::string& extraSections = "") {
  std::string s = "MeshVersionFormatted 2\nDimension 3\n";
  s += fmt::format("Vertices\n{}\n", mesh.V.rows());
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    s += fmt::format("{:.17g} {:.17g} {:.17g} 0\n", mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2));
  s += extraSections;
  s += fmt::format("Tetrahedra\n{}\n", mesh.T.rows());
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t)
    s += fmt::format("{} {} {} {} {}\n", mesh.T(t, 0) + 1, mesh.T(t, 1) + 1, mesh.T(t, 2) + 1,
                     mesh.T(t, 3) + 1, mesh.regionOf(t));
  return s + "End\n";
}

TEST(MeditReader, TheSectionsMmgAndCgalWriteReadToTheCube) {
  const TetMesh cube = test::cubeMesh();
  // Comments, the dimension on its own line, and sections the reader skips.
  std::string text = meditText(cube,
                               "# the boundary, skipped\nTriangles\n2\n1 2 3 7\n2 3 4 7\n"
                               "Edges 1\n1 2 0\nCorners\n1\n1\nRequiredVertices 2 1 2\n"
                               "Ridges\n1\n1\nNormals\n1\n0 0 1\nNormalAtVertices\n1\n1 1\n");
  text.replace(text.find("Dimension 3"), 11, "Dimension\n3 # a volume");
  TempDir dir;
  const TetMesh read = readTetMesh(writeText(dir.file("cube.mesh"), text));
  EXPECT_EQ(read.V, cube.V);
  EXPECT_EQ(read.T, cube.T);
  EXPECT_EQ(read.region, cube.region);
}

TEST(MeditReader, ABoxReadsAsItsVtuDoes) {
  const TetMesh box = makeBoxMesh(Vec3(0.12, 0.05, 0.03), 6, 3, 2);
  TempDir dir;
  writeTetMesh(dir.file("box.vtu"), box);
  const TetMesh fromVtu = readTetMesh(dir.file("box.vtu"));
  const TetMesh fromMedit = readTetMesh(writeText(dir.file("box.mesh"), meditText(box)));
  EXPECT_EQ(fromMedit.V, fromVtu.V);
  EXPECT_EQ(fromMedit.T, fromVtu.T);
  EXPECT_EQ(fromMedit.region.size() ? fromMedit.region.maxCoeff() : 0, 0);
}

TEST(MeditReader, MalformedFilesAreOneLineErrors) {
  TempDir dir;
  const std::string p = dir.file("bad.mesh");
  const auto expectError = [&](const std::string& text, const std::string& message) {
    writeText(p, text);
    EXPECT_INPUT_ERROR(p + message, readTetMesh(p));
  };
  const std::string head = "MeshVersionFormatted 1\nDimension 3\n";
  const std::string vertices = head + "Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n";
  expectError("solid x\n",
              ":1: 'solid'; expected 'MeshVersionFormatted' (an ASCII Medit .mesh file)");
  expectError("MeshVersionFormatted 7\n", ":1: MeshVersionFormatted 7; expected 1 to 4");
  expectError("MeshVersionFormatted 1\nDimension 2\n",
              ":2: Dimension 2; expected 3 (a volume mesh)");
  expectError("MeshVersionFormatted 1\n", ":2: 'the end of the file'; expected 'Dimension 3'");
  expectError(head + "Vertices\n2\n0 0 0 0\n1 abc 0 0\n",
              ":6: vertex 2 y is 'abc'; expected a finite number");
  expectError(head + "Vertices\n1000000\n0 0 0 0\n",
              ":4: Vertices 1000000; expected a count in [0, 2^31) that the 9 bytes left can hold");
  expectError(vertices + "Tetrahedra\n1\n1 2 3 0 1\n",
              ":11: tetrahedron 1 names vertex 0; expected a number from 1 (Medit numbers vertices "
              "from 1)");
  expectError(vertices + "Tetrahedra\n1\n1 2 3 5 1\nEnd\n",
              ":11: tetrahedron 1 names vertex 5; expected 1 to 4 (Medit numbers vertices from 1)");
  expectError(vertices + "Tetrahedra\n1\n1 2 3\n",
              ":10: Tetrahedra 1; expected a count in [0, 2^31) that the 7 bytes left can hold");
  expectError(vertices + "Tetrahedra\n1\n1 2 3 4\n",
              ":12: tetrahedron 1 reference is 'the end of the file'; expected an integer");
  expectError(vertices + "End\n", ": no tetrahedra (a Tetrahedra section); expected a volume mesh");
  expectError(vertices + "Vertices 0\n", ":9: a second Vertices section; expected one");
  expectError(vertices + "Pyramids\n1\n1 2 3 4 5 0\n",
              ":9: section 'Pyramids' unknown; expected Vertices, Tetrahedra, another usual "
              "section (Triangles, Edges, Corners, Ridges, Normals, ...) or End");
  expectError(vertices + "Triangles\n1\n1 2 x 0\n", ":11: Triangles 1 is 'x'; expected 4 numbers");
  // Validation names the tetrahedron by its number and line, as the file has it.
  expectError(vertices + "Tetrahedra\n2\n1 2 3 4 0\n1 3 2 4 0\nEnd\n",
              ":12: tetrahedron 2 has the same 4 nodes as tetrahedron 1 (line 11); expected each "
              "tetrahedron once");
  const std::string meshb = writeText(dir.file("liver.meshb"), "binary");
  EXPECT_INPUT_ERROR(meshb +
                         ": binary Medit files are not supported; expected an ASCII .mesh (e.g. "
                         "saved by MMG or Gmsh as .mesh)",
                     readTetMesh(meshb));
}

}  // namespace
}  // namespace bcassim
