// Triangle surfaces (.obj, .stl, .vtp, .vtk) and point sets: round trips and input errors.
#include <gtest/gtest.h>

#include "bcassim/io/MeshWriter.h"
#include "bcassim/io/SurfaceReader.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::TempDir;
using test::tetSurface;
using test::writeText;

class SurfaceRoundTrip : public ::testing::TestWithParam<const char*> {};

// tetSurface() has float-representable coordinates, so even binary STL (float) is exact.
TEST_P(SurfaceRoundTrip, WriteThenReadGivesTheSameSurface) {
  TempDir dir;
  const TriMesh mesh = tetSurface();
  const std::string path = dir.file(std::string("tet") + GetParam());
  writeSurface(path, mesh);
  const TriMesh back = readSurface(path);
  EXPECT_EQ(back.V, mesh.V);
  EXPECT_EQ(back.F, mesh.F);
}

INSTANTIATE_TEST_SUITE_P(Formats, SurfaceRoundTrip,
                         ::testing::Values(".obj", ".stl", ".vtp", ".vtk"));

TEST(SurfaceIo, DoublePrecisionSurvivesObjVtpAndVtk) {
  TempDir dir;
  TriMesh mesh = tetSurface();
  mesh.V.col(0).array() += 1.0 / 3.0;
  for (const char* ext : {".obj", ".vtp", ".vtk"}) {
    const std::string path = dir.file(std::string("tet") + ext);
    writeSurface(path, mesh);
    EXPECT_EQ(readSurface(path).V, mesh.V) << ext;
  }
}

TEST(ObjReader, FaceFormsPolygonsAndNegativeIndices) {
  TempDir dir;
  const std::string path = writeText(dir.file("quad.obj"),
                                     "# a quad and a triangle\nmtllib x.mtl\no quad\n"
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\n"
                                     "vn 0 0 1\nvt 0 0\ns 1\n"
                                     "f 1/1/1 2/1/1 3/1/1 4/1/1\n"
                                     "v 0 0 1\n"
                                     "f -1//1 1//1 2//1\n"
                                     "f 5/1 3/1 4/1\n");
  const TriMesh mesh = readSurface(path);
  ASSERT_EQ(mesh.V.rows(), 5);
  Eigen::MatrixX3i F(4, 3);
  F << 0, 1, 2, 0, 2, 3, 4, 0, 1, 4, 2, 3;
  EXPECT_EQ(mesh.F, F);
  EXPECT_EQ(mesh.V(3, 1), 1.0);
}

TEST(ObjReader, FaceIndexBeyondVertices) {
  TempDir dir;
  const std::string path =
      writeText(dir.file("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 9\n");
  EXPECT_INPUT_ERROR(path + ":6: face refers to vertex 9, but the file defines 4 vertices",
                     readSurface(path));
}

TEST(ObjReader, FaceIndexZero) {
  TempDir dir;
  const std::string path = writeText(dir.file("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  EXPECT_INPUT_ERROR(path + ":4: face vertex index 0 is invalid; OBJ indices start at 1",
                     readSurface(path));
}

TEST(ObjReader, NonNumericFaceIndex) {
  TempDir dir;
  const std::string path = writeText(dir.file("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 two 3\n");
  EXPECT_INPUT_ERROR(path + ":4: expected a vertex index in face vertex 'two'", readSurface(path));
}

TEST(ObjReader, RelativeIndexBeforeFirstVertex) {
  TempDir dir;
  const std::string path = writeText(dir.file("bad.obj"), "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n");
  EXPECT_INPUT_ERROR(path +
                         ":3: relative face vertex index -3 goes before the first vertex (2 "
                         "defined so far)",
                     readSurface(path));
}

TEST(ObjReader, NanVertex) {
  TempDir dir;
  const std::string path = writeText(dir.file("bad.obj"), "v 0 0 0\nv 1 nan 0\n");
  EXPECT_INPUT_ERROR(path + ":2: vertex coordinate y is not a finite number ('nan')",
                     readSurface(path));
}

TEST(SurfaceIo, UnknownExtensionAndMissingFile) {
  EXPECT_INPUT_ERROR(
      "s.off: unsupported surface format '.off'; expected .stl, .obj, .ply, .vtk or .vtp",
      readSurface("s.off"));
  TempDir dir;
  EXPECT_INPUT_ERROR(dir.file("no.stl") + ": cannot open file", readSurface(dir.file("no.stl")));
}

TEST(PointReader, VtpPointCloudAndLegacyVertices) {
  TempDir dir;
  Eigen::MatrixX3d points(3, 3);
  points << 0.02, 0, 0.08, 1.0 / 3.0, 0.5, -2, 7, 8, 9;
  writePointCloud(dir.file("obs.vtp"), points);
  EXPECT_EQ(readPoints(dir.file("obs.vtp")), points);
  const std::string legacy =
      writeText(dir.file("obs.vtk"),
                "# vtk DataFile Version 4.0\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                "POINTS 3 float\n0.5 0 0.25\t1 2 3\n4 5 6\nCELLS 3 6\n1 0\n1 1\n1 2\n"
                "CELL_TYPES 3\n1\n1\n1\n");
  Eigen::MatrixX3d expected(3, 3);
  expected << 0.5, 0, 0.25, 1, 2, 3, 4, 5, 6;
  EXPECT_EQ(readPoints(legacy), expected);
}

TEST(PointReader, CsvWithAndWithoutHeader) {
  TempDir dir;
  Eigen::MatrixX3d expected(2, 3);
  expected << 0.1, 0.2, 0.3, -1, 2e-3, 4;
  EXPECT_EQ(readPoints(writeText(dir.file("a.csv"), "0.1,0.2,0.3\n-1, 2e-3 ,4\n")), expected);
  EXPECT_EQ(readPoints(writeText(dir.file("b.csv"), "id,z,y,x\n0,0.3,0.2,0.1\n1,4,2e-3,-1\n")),
            expected);
  const std::string bad = writeText(dir.file("c.csv"), "1,2\n");
  EXPECT_INPUT_ERROR(bad + ":1: expected 3 fields (x,y,z), got 2", readPoints(bad));
}

}  // namespace
}  // namespace bcassim
