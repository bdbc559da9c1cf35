// Tet meshes through VTK files: .vtu and legacy .vtk round trips, fields, and input errors.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "bcassim/Types.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/MeshWriter.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::cubeMesh;
using test::TempDir;
using test::writeText;

// Coordinates that need all 17 significant digits, so a lossy writer would show.
TetMesh irregularCube() {
  TetMesh mesh = cubeMesh();
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    mesh.V.row(i) = 0.1 * mesh.V.row(i) + Eigen::RowVector3d(1.0 / 3.0, 2.0 / 7.0, 1e-3 / 9.0);
  return mesh;
}

class TetMeshRoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(TetMeshRoundTrip, WriteThenReadGivesTheSameMesh) {
  TempDir dir;
  const TetMesh mesh = irregularCube();
  const std::string path = dir.file(std::string("cube") + GetParam());
  writeTetMesh(path, mesh);
  const TetMesh back = readTetMesh(path);
  EXPECT_EQ(back.V, mesh.V);
  EXPECT_EQ(back.T, mesh.T);
  EXPECT_EQ(back.region, mesh.region);
}

TEST_P(TetMeshRoundTrip, PositionsReplaceRestCoordinates) {
  TempDir dir;
  const TetMesh mesh = irregularCube();
  Eigen::VectorXd x(3 * mesh.numNodes());
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    node(x, i) = mesh.V.row(i).transpose() + 1e-3 * Eigen::Vector3d(std::sin(i), 1.0 / 7.0, i);
  const std::string path = dir.file(std::string("moved") + GetParam());
  TetMesh moved = mesh;
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i) moved.V.row(i) = node(x, i).transpose();
  writeTetMesh(path, mesh, x);
  EXPECT_EQ(readTetMesh(path).V, moved.V);
}

INSTANTIATE_TEST_SUITE_P(Formats, TetMeshRoundTrip, ::testing::Values(".vtu", ".vtk"));

TEST(MeshWriter, WritesNamedPointAndCellFields) {
  TempDir dir;
  const TetMesh mesh = cubeMesh();
  FieldSet fields;
  fields.pointScalars.emplace_back("pressure_Pa", Eigen::VectorXd::LinSpaced(8, 0.0, 7.0));
  fields.pointVectors.emplace_back("displacement_m", Eigen::MatrixX3d::Constant(8, 3, 0.25));
  fields.cellScalars.emplace_back("stiffness_Pa", Eigen::VectorXd::Constant(5, 4500.0));
  const std::string path = dir.file("fields.vtu");
  writeTetMesh(path, mesh, Eigen::VectorXd(), fields);

  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  vtkDataArray* p = grid->GetPointData()->GetArray("pressure_Pa");
  vtkDataArray* u = grid->GetPointData()->GetArray("displacement_m");
  vtkDataArray* k = grid->GetCellData()->GetArray("stiffness_Pa");
  vtkDataArray* r = grid->GetCellData()->GetArray("region");
  ASSERT_TRUE(p && u && k && r);
  EXPECT_EQ(p->GetTuple1(7), 7.0);
  EXPECT_EQ(u->GetNumberOfComponents(), 3);
  EXPECT_EQ(u->GetComponent(5, 2), 0.25);
  EXPECT_EQ(k->GetTuple1(4), 4500.0);
  EXPECT_EQ(r->GetTuple1(4), 2.0);
}

TEST(MeshWriter, RejectsFieldOfWrongSize) {
  TempDir dir;
  FieldSet fields;
  fields.pointScalars.emplace_back("short", Eigen::VectorXd::Zero(3));
  EXPECT_THROW(writeTetMesh(dir.file("bad.vtu"), cubeMesh(), Eigen::VectorXd(), fields),
               std::invalid_argument);
}

TEST(MeshReader, MissingFile) {
  TempDir dir;
  const std::string path = dir.file("absent.vtu");
  EXPECT_INPUT_ERROR(path + ": cannot open file", readTetMesh(path));
}

TEST(MeshReader, UnknownExtension) {
  EXPECT_INPUT_ERROR(
      "liver.ply: unsupported tetrahedral mesh format '.ply'; expected .vtk, .vtu, .msh or .mesh",
      readTetMesh("liver.ply"));
}

// A legacy file as other tools write it: ASCII, float points, float region field.
std::string legacyCube(const std::string& y2 = "1") {
  return "# vtk DataFile Version 2.0\ncube\nASCII\nDATASET UNSTRUCTURED_GRID\n"
         "POINTS 8 float\n0 0 0\n1 0 0\n0 " +
         y2 +
         " 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
         "CELLS 6 28\n2 0 1\n4 0 1 2 4\n4 1 3 2 7\n4 1 5 7 4\n4 2 7 6 4\n4 1 2 4 7\n"
         "CELL_TYPES 6\n3\n10\n10\n10\n10\n10\n"
         "CELL_DATA 6\nSCALARS dataset float 1\nLOOKUP_TABLE default\n9 1 1 1 1 2\n";
}

TEST(MeshReader, LegacyAsciiWithFloatRegionFieldAndOtherCells) {
  TempDir dir;
  const TetMesh back = readTetMesh(writeText(dir.file("cube.vtk"), legacyCube()));
  const TetMesh cube = cubeMesh();
  EXPECT_EQ(back.V, cube.V);
  EXPECT_EQ(back.T, cube.T);
  EXPECT_EQ(back.region, cube.region);
}

TEST(MeshReader, NamedRegionFieldMustExist) {
  TempDir dir;
  const std::string path = writeText(dir.file("cube.vtk"), legacyCube());
  EXPECT_INPUT_ERROR(path + ": no numeric cell field 'material'; the file has 'dataset'",
                     readTetMesh(path, "material"));
}

TEST(MeshReader, NanCoordinateInLegacyVtk) {
  TempDir dir;
  const std::string path = writeText(dir.file("nan.vtk"), legacyCube("nan"));
  EXPECT_INPUT_ERROR(path + ":8: value 'nan' is not a finite number", readTetMesh(path));
}

TEST(MeshReader, VtkErrorsAreNotPrinted) {
  TempDir dir;
  const std::string path = writeText(dir.file("nan.vtk"), legacyCube("nan"));
  ::testing::internal::CaptureStderr();
  ::testing::internal::CaptureStdout();
  EXPECT_THROW(readTetMesh(path), InputError);
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(MeshReader, TruncatedLegacyVtk) {
  TempDir dir;
  std::string text = legacyCube();
  text.erase(text.find("0 1 1\n"));
  const std::string path = writeText(dir.file("cut.vtk"), text);
  // Refused at the count, before anything is allocated for it.
  EXPECT_INPUT_ERROR(path +
                         ":5: POINTS 8 needs 24 values (at least 47 bytes), but the file has only "
                         "37 bytes left",
                     readTetMesh(path));
}

TEST(MeshReader, LegacyFileThatIsNotAGrid) {
  TempDir dir;
  const std::string path =
      writeText(dir.file("poly.vtk"),
                "# vtk DataFile Version 2.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\n");
  EXPECT_INPUT_ERROR(path +
                         ": not a legacy VTK unstructured grid; expected 'DATASET "
                         "UNSTRUCTURED_GRID' with tetrahedra",
                     readTetMesh(path));
}

TEST(MeshReader, GarbageVtu) {
  TempDir dir;
  const std::string path = writeText(dir.file("junk.vtu"), "this is not xml\n");
  const std::string message = test::inputErrorOf([&] { readTetMesh(path); });
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(MeshReader, InvertedTetInVtu) {
  TempDir dir;
  TetMesh mesh = cubeMesh();
  std::swap(mesh.T(3, 0), mesh.T(3, 1));
  const std::string path = dir.file("inv.vtu");
  writeTetMesh(path, mesh);
  EXPECT_INPUT_ERROR(path +
                         ": cell 3 is inverted (signed volume -0.167 m^3); expected the same "
                         "orientation as the other tets",
                     readTetMesh(path));
}

TEST(MeshWriter, PolyLinesAndPointCloudAreVtp) {
  TempDir dir;
  Eigen::MatrixX3d points(3, 3);
  points << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  Eigen::MatrixX2i segments(2, 2);
  segments << 0, 1, 1, 2;
  FieldSet fields;
  fields.cellScalars.emplace_back("stiffness_N_per_m", Eigen::Vector2d(10.0, 20.0));
  writePolyLines(dir.file("springs.vtp"), points, segments, fields);
  writePointCloud(dir.file("markers.vtp"), points);
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.file("springs.vtp")));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.file("markers.vtp")));
  EXPECT_INPUT_ERROR(dir.file("m.csv") + ": unsupported point set format '.csv'; expected .vtp",
                     writePointCloud(dir.file("m.csv"), points));
}

}  // namespace
}  // namespace bcassim
