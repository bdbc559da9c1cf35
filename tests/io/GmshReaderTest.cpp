// Gmsh .msh reading: formats 1, 2.2 and 4.1, and the one-line errors of malformed files.
#include <gtest/gtest.h>

#include "bcassim/io/MeshReader.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::cubeMesh;
using test::TempDir;
using test::writeText;

// Node tags are i+10 to check that tags are mapped, not used as indices; a triangle and a
// point element are there to be ignored.
std::string cubeV2() {
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
         "$PhysicalNames\n2\n3 1 \"corners\"\n3 2 \"centre\"\n$EndPhysicalNames\n"
         "$Nodes\n8\n"
         "10 0 0 0\n11 1 0 0\n12 0 1 0\n13 1 1 0\n14 0 0 1\n15 1 0 1\n16 0 1 1\n17 1 1 1\n"
         "$EndNodes\n"
         "$Elements\n7\n"
         "1 15 2 0 1 10\n"
         "2 2 2 5 1 10 11 12\n"
         "3 4 2 1 1 10 11 12 14\n"
         "4 4 2 1 1 11 13 12 17\n"
         "5 4 2 1 1 11 15 17 14\n"
         "6 4 2 1 1 12 17 16 14\n"
         "7 4 2 2 1 11 12 14 17\n"
         "$EndElements\n";
}

std::string cubeV41() {
  return "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
         "$Entities\n0 0 1 2\n"
         "1 0 0 0 1 1 1 0 0\n"
         "1 0 0 0 1 1 1 1 1 0\n"
         "2 0 0 0 1 1 1 1 2 0\n"
         "$EndEntities\n"
         "$Nodes\n2 8 1 8\n"
         "3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
         "3 2 0 4\n5\n6\n7\n8\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
         "$EndNodes\n"
         "$Elements\n3 6 1 6\n"
         "2 1 2 1\n1 1 2 3\n"
         "3 1 4 4\n2 1 2 3 5\n3 2 4 3 8\n4 2 6 8 5\n5 3 8 7 5\n"
         "3 2 4 1\n6 2 3 5 8\n"
         "$EndElements\n";
}

std::string cubeV1() {
  return "$NOD\n8\n"
         "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n5 0 0 1\n6 1 0 1\n7 0 1 1\n8 1 1 1\n"
         "$ENDNOD\n$ELM\n6\n"
         "1 2 7 7 3 1 2 3\n"
         "2 4 1 1 4 1 2 3 5\n"
         "3 4 1 1 4 2 4 3 8\n"
         "4 4 1 1 4 2 6 8 5\n"
         "5 4 1 1 4 3 8 7 5\n"
         "6 4 2 2 4 2 3 5 8\n"
         "$ENDELM\n";
}

void expectCube(const TetMesh& mesh) {
  const TetMesh cube = cubeMesh();
  EXPECT_EQ(mesh.V, cube.V);
  EXPECT_EQ(mesh.T, cube.T);
  EXPECT_EQ(mesh.region, cube.region);
}

TEST(GmshReader, ReadsVersion22) {
  TempDir dir;
  expectCube(readTetMesh(writeText(dir.file("cube.msh"), cubeV2())));
}

TEST(GmshReader, ReadsVersion41WithPhysicalTagsFromEntities) {
  TempDir dir;
  expectCube(readTetMesh(writeText(dir.file("cube.msh"), cubeV41())));
}

TEST(GmshReader, ReadsVersion1) {
  TempDir dir;
  expectCube(readTetMesh(writeText(dir.file("cube.msh"), cubeV1())));
}

TEST(GmshReader, AcceptsWindowsLineEndingsAndBlankLines) {
  std::string text;
  for (char c : cubeV2()) {
    if (c == '\n')
      text += "\r\n";
    else
      text += c;
  }
  text.insert(text.find("$Nodes"), "\r\n");
  TempDir dir;
  expectCube(readTetMesh(writeText(dir.file("cube.msh"), text)));
}

TEST(GmshReader, TruncatedVersion22) {
  TempDir dir;
  const std::string path = writeText(dir.file("cut.msh"),
                                     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n"
                                     "10 0 0 0\n11 1 0 0\n12 0 1 0\n");
  EXPECT_INPUT_ERROR(path + ": unexpected end of file in $Nodes (line 8); expected 8 nodes, read 3",
                     readTetMesh(path));
}

TEST(GmshReader, MissingEndElementsVersion22) {
  TempDir dir;
  std::string text = cubeV2();
  text.erase(text.find("$EndElements"));
  const std::string path = writeText(dir.file("cut.msh"), text);
  EXPECT_INPUT_ERROR(
      path + ": unexpected end of file in $Elements (line 28); expected $EndElements",
      readTetMesh(path));
}

TEST(GmshReader, EndNodesBeforeAllNodesVersion22) {
  TempDir dir;
  std::string text = cubeV2();
  text.erase(text.find("17 1 1 1\n"), 9);
  const std::string path = writeText(dir.file("short.msh"), text);
  EXPECT_INPUT_ERROR(path + ":18: expected 8 nodes in $Nodes, got '$EndNodes' after 7",
                     readTetMesh(path));
}

TEST(GmshReader, TruncatedVersion41) {
  TempDir dir;
  std::string text = cubeV41();
  text.erase(text.find("4 2 6 8 5\n"));
  const std::string path = writeText(dir.file("cut.msh"), text);
  EXPECT_INPUT_ERROR(
      path + ": unexpected end of file in $Elements (line 37); expected 6 elements, read 3",
      readTetMesh(path));
}

TEST(GmshReader, TruncatedNodesVersion41) {
  TempDir dir;
  std::string text = cubeV41();
  text.erase(text.find("0 0 1\n"));
  const std::string path = writeText(dir.file("cut.msh"), text);
  EXPECT_INPUT_ERROR(
      path + ": unexpected end of file in $Nodes (line 25); expected 8 nodes, read 4",
      readTetMesh(path));
}

TEST(GmshReader, NanCoordinate) {
  TempDir dir;
  std::string text = cubeV2();
  text.replace(text.find("12 0 1 0"), 8, "12 0 nan 0");
  const std::string path = writeText(dir.file("nan.msh"), text);
  EXPECT_INPUT_ERROR(path + ":13: coordinate y of node 12 is not a finite number ('nan')",
                     readTetMesh(path));
}

TEST(GmshReader, NanCoordinateVersion41) {
  TempDir dir;
  std::string text = cubeV41();
  text.replace(text.find("1 1 1\n$EndNodes"), 5, "1 1 NaN");
  const std::string path = writeText(dir.file("nan.msh"), text);
  EXPECT_INPUT_ERROR(path + ":29: coordinate z of node 8 is not a finite number ('NaN')",
                     readTetMesh(path));
}

TEST(GmshReader, NonNumericField) {
  TempDir dir;
  std::string text = cubeV2();
  text.replace(text.find("11 1 0 0"), 8, "11 1x 0 0");
  const std::string path = writeText(dir.file("bad.msh"), text);
  EXPECT_INPUT_ERROR(path + ":12: expected a number for coordinate x of node 11, got '1x'",
                     readTetMesh(path));
}

TEST(GmshReader, NonNumericElementType) {
  TempDir dir;
  std::string text = cubeV2();
  text.replace(text.find("5 4 2 1 1"), 9, "5 tet 2 1 1");
  const std::string path = writeText(dir.file("bad.msh"), text);
  EXPECT_INPUT_ERROR(path + ":26: expected an integer for the element type, got 'tet'",
                     readTetMesh(path));
}

TEST(GmshReader, UndefinedNode) {
  TempDir dir;
  std::string text = cubeV2();
  text.replace(text.find("11 13 12 17"), 11, "11 13 12 99");
  const std::string path = writeText(dir.file("bad.msh"), text);
  EXPECT_INPUT_ERROR(path + ":25: element 4 refers to node 99, which is not defined in $Nodes",
                     readTetMesh(path));
}

TEST(GmshReader, WrongFieldCountInElementLine) {
  TempDir dir;
  std::string text = cubeV2();
  text.replace(text.find("11 15 17 14"), 11, "11 15 17");
  const std::string path = writeText(dir.file("bad.msh"), text);
  EXPECT_INPUT_ERROR(
      path + ":26: expected 9 fields in an element line (3, 2 tags, 4 nodes of type 4), got 8",
      readTetMesh(path));
}

TEST(GmshReader, BinaryIsRejected) {
  TempDir dir;
  const std::string path =
      writeText(dir.file("bin.msh"), "$MeshFormat\n4.1 1 8\n\x01\x00\x00\x00\n$EndMeshFormat\n");
  EXPECT_INPUT_ERROR(path +
                         ":2: binary Gmsh files are not supported; expected ASCII (file-type "
                         "0), e.g. saved with gmsh -format msh22 or msh41 without -bin",
                     readTetMesh(path));
}

TEST(GmshReader, UnsupportedVersion) {
  TempDir dir;
  const std::string path = writeText(dir.file("v4.msh"), "$MeshFormat\n4 0 8\n$EndMeshFormat\n");
  EXPECT_INPUT_ERROR(path + ":2: Gmsh format version 4 is not supported; expected 2.2 or 4.1",
                     readTetMesh(path));
}

TEST(GmshReader, NoTetrahedra) {
  TempDir dir;
  const std::string path = writeText(dir.file("tri.msh"),
                                     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n"
                                     "1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                                     "$Elements\n1\n1 2 2 0 1 1 2 3\n$EndElements\n");
  EXPECT_INPUT_ERROR(path + ": no tetrahedra (Gmsh element type 4); expected a volume mesh",
                     readTetMesh(path));
}

TEST(GmshReader, InvertedTet) {
  TempDir dir;
  std::string text = cubeV2();
  text.replace(text.find("11 15 17 14"), 11, "11 17 15 14");
  const std::string path = writeText(dir.file("inv.msh"), text);
  // Named by its element tag and line, as the file numbers it (it is the third tet).
  EXPECT_INPUT_ERROR(path +
                         ":26: element 5 is inverted (signed volume -0.167 m^3); expected the same "
                         "orientation as the other tets",
                     readTetMesh(path));
}

}  // namespace
}  // namespace bcassim
