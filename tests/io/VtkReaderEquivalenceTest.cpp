// Our bounded VTK and STL readers against VTK's own: files written by VTK's writers in every mode
// they offer, and the shared data, must read to the same points, tets, regions and triangles, bit
// for bit, as VTK's readers gave them (how bcassim read them before).
#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkPolyDataWriter.h>
#include <vtkSTLReader.h>
#include <vtkSTLWriter.h>
#include <vtkTriangleFilter.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridReader.h>
#include <vtkUnstructuredGridWriter.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <random>
#include <string>

#include "bcassim/Types.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/SurfaceReader.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/MeshValidation.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::TempDir;

// --- the reference: VTK's readers, as io/MeshReader.cpp and io/SurfaceReader.cpp used them ---

Eigen::MatrixX3d pointsOf(vtkPointSet* data) {
  Eigen::MatrixX3d V(data->GetNumberOfPoints(), 3);
  double p[3];
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i) {
    data->GetPoint(i, p);
    V.row(i) << p[0], p[1], p[2];
  }
  return V;
}

TetMesh referenceTets(const std::string& path) {
  vtkSmartPointer<vtkUnstructuredGrid> grid;
  if (path.substr(path.size() - 4) == ".vtu") {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    grid = reader->GetOutput();
  } else {
    vtkNew<vtkUnstructuredGridReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    grid = reader->GetOutput();
  }
  TetMesh mesh;
  mesh.V = pointsOf(grid);
  std::vector<vtkIdType> tets;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    if (grid->GetCellType(c) == VTK_TETRA) tets.push_back(c);
  mesh.T.resize(static_cast<Eigen::Index>(tets.size()), 4);
  vtkNew<vtkIdList> ids;
  for (size_t t = 0; t < tets.size(); ++t) {
    grid->GetCellPoints(tets[t], ids);
    for (int k = 0; k < 4; ++k) mesh.T(static_cast<Eigen::Index>(t), k) = ids->GetId(k);
  }
  vtkDataArray* region = nullptr;
  for (const char* name : {"dataset", "region", "gmsh:physical", "CellEntityIds"})
    if (!region) region = grid->GetCellData()->GetArray(name);
  if (region) {
    mesh.region.resize(mesh.T.rows());
    for (size_t t = 0; t < tets.size(); ++t)
      mesh.region(static_cast<Eigen::Index>(t)) = static_cast<int>(region->GetTuple1(tets[t]));
  }
  validateTetMesh(mesh, path);
  return mesh;
}

template <class Reader>
TriMesh referenceSurface(const std::string& path) {
  vtkNew<Reader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(reader->GetOutput());
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  triangulate->Update();
  TriMesh mesh;
  mesh.V = pointsOf(reader->GetOutput());
  std::vector<int> faces;
  vtkNew<vtkIdList> ids;
  vtkCellArray* polys = triangulate->GetOutput()->GetPolys();
  polys->InitTraversal();
  while (polys->GetNextCell(ids))
    if (ids->GetNumberOfIds() == 3)
      for (int k = 0; k < 3; ++k) faces.push_back(static_cast<int>(ids->GetId(k)));
  mesh.F = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      faces.data(), static_cast<Eigen::Index>(faces.size() / 3), 3);
  return mesh;
}

void expectSameTets(const TetMesh& ours, const TetMesh& vtk) {
  ASSERT_EQ(ours.V.rows(), vtk.V.rows());
  EXPECT_TRUE(ours.V == vtk.V);  // bit for bit, not approximately
  EXPECT_EQ(ours.T, vtk.T);
  EXPECT_EQ(ours.region, vtk.region);
}

void expectSameSurface(const TriMesh& ours, const TriMesh& vtk) {
  ASSERT_EQ(ours.V.rows(), vtk.V.rows());
  EXPECT_TRUE(ours.V == vtk.V);
  EXPECT_EQ(ours.F, vtk.F);
}

// --- test data: a grid with irregular coordinates, an int region field, boundary triangles, and
// point and cell data of other kinds, large enough for several compression blocks ---

vtkSmartPointer<vtkUnstructuredGrid> testGrid(bool doublePoints) {
  TetMesh mesh = makeBoxMesh(Vec3(0.2, 0.1, 0.1), 14, 8, 8);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    for (int k = 0; k < 3; ++k) mesh.V(i, k) += jitter(rng) / 3.0;
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataType(doublePoints ? VTK_DOUBLE : VTK_FLOAT);
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    points->InsertNextPoint(mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2));
  grid->SetPoints(points);
  vtkNew<vtkIntArray> region;
  region->SetName("region");
  vtkNew<vtkDoubleArray> vectors;
  vectors->SetName("force");
  vectors->SetNumberOfComponents(3);
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    const vtkIdType ids[4] = {mesh.T(t, 0), mesh.T(t, 1), mesh.T(t, 2), mesh.T(t, 3)};
    grid->InsertNextCell(VTK_TETRA, 4, ids);
    region->InsertNextValue(static_cast<int>(t % 3) + 1);
    vectors->InsertNextTuple3(0.5 * t, 1.0 / (t + 1), -2.0);
    if (t % 50 == 0) {  // a boundary-like triangle between the tets
      grid->InsertNextCell(VTK_TRIANGLE, 3, ids);
      region->InsertNextValue(9);
      vectors->InsertNextTuple3(0, 0, 0);
    }
  }
  grid->GetCellData()->AddArray(region);
  grid->GetCellData()->SetVectors(vectors);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("temperature_K");
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i) temperature->InsertNextValue(300.0 + i);
  grid->GetPointData()->SetScalars(temperature);
  return grid;
}

TEST(VtkReaderEquivalence, LegacyGridsInEveryMode) {
  TempDir dir;
  for (const bool binary : {false, true})
    for (const int version : {42, 51})
      for (const bool doublePoints : {false, true}) {
        SCOPED_TRACE(::testing::Message() << "binary " << binary << " version " << version
                                          << " double " << doublePoints);
        const std::string path = dir.file("grid.vtk");
        vtkNew<vtkUnstructuredGridWriter> writer;
        writer->SetFileName(path.c_str());
        writer->SetInputData(testGrid(doublePoints));
        writer->SetFileVersion(version);
        if (binary) writer->SetFileTypeToBinary();
        ASSERT_EQ(writer->Write(), 1);
        expectSameTets(readTetMesh(path), referenceTets(path));
      }
}

TEST(VtkReaderEquivalence, XmlGridsInEveryMode) {
  TempDir dir;
  int variant = 0;
  for (const int mode : {0, 1, 2, 3})  // ascii, inline binary, appended raw, appended base64
    for (const int compressor : {0, 1, 2, 3}) {
      if (mode == 0 && compressor > 0) continue;
      ++variant;
      SCOPED_TRACE(::testing::Message() << "mode " << mode << " compressor " << compressor);
      const std::string path = dir.file("grid.vtu");
      vtkNew<vtkXMLUnstructuredGridWriter> writer;
      writer->SetFileName(path.c_str());
      writer->SetInputData(testGrid(variant % 2 == 0));
      if (mode == 0) writer->SetDataModeToAscii();
      if (mode == 1) writer->SetDataModeToBinary();
      if (mode >= 2) writer->SetDataModeToAppended();
      writer->SetEncodeAppendedData(mode == 3);
      writer->SetCompressorType(compressor);  // NONE, ZLIB, LZ4, LZMA
      writer->SetBlockSize(1 << 12);          // several blocks per array
      variant % 2 ? writer->SetHeaderTypeToUInt64() : writer->SetHeaderTypeToUInt32();
      variant % 3 ? writer->SetIdTypeToInt64() : writer->SetIdTypeToInt32();
      ASSERT_EQ(writer->Write(), 1);
      expectSameTets(readTetMesh(path), referenceTets(path));
    }
}

// Triangles, a quad, a pentagon (VTK's ear cutting), a triangle strip, and vertices and lines that
// are not part of the surface.
vtkSmartPointer<vtkPolyData> testSurface() {
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coordinate(0.0, 1.0);
  for (int i = 0; i < 40; ++i) {
    const int row = i / 8, column = i % 8;  // a jittered 8 x 5 grid
    points->InsertNextPoint(column + coordinate(rng) / 7, row + coordinate(rng) / 7,
                            coordinate(rng) / 3);
  }
  poly->SetPoints(points);
  vtkNew<vtkCellArray> polys, strips, verts, lines;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 6; ++c) {
      const vtkIdType a = 8 * r + c, b = a + 1, d = a + 8, e = a + 9;
      const vtkIdType tri1[3] = {a, b, e}, tri2[3] = {a, e, d};
      polys->InsertNextCell(3, tri1);
      polys->InsertNextCell(3, tri2);
    }
  const vtkIdType quad[4] = {6, 7, 15, 14};
  const vtkIdType pentagon[5] = {30, 31, 39, 38, 37};
  polys->InsertNextCell(4, quad);
  polys->InsertNextCell(5, pentagon);
  const vtkIdType strip[6] = {32, 24, 33, 25, 34, 26};
  strips->InsertNextCell(6, strip);
  const vtkIdType vertex[1] = {0}, line[2] = {1, 2};
  verts->InsertNextCell(1, vertex);
  lines->InsertNextCell(2, line);
  poly->SetPolys(polys);
  poly->SetStrips(strips);
  poly->SetVerts(verts);
  poly->SetLines(lines);
  return poly;
}

TEST(VtkReaderEquivalence, LegacyAndXmlSurfaces) {
  TempDir dir;
  for (const bool binary : {false, true})
    for (const int version : {42, 51}) {
      SCOPED_TRACE(::testing::Message() << "legacy binary " << binary << " version " << version);
      const std::string path = dir.file("surface.vtk");
      vtkNew<vtkPolyDataWriter> writer;
      writer->SetFileName(path.c_str());
      writer->SetInputData(testSurface());
      writer->SetFileVersion(version);
      if (binary) writer->SetFileTypeToBinary();
      ASSERT_EQ(writer->Write(), 1);
      expectSameSurface(readSurface(path), referenceSurface<vtkPolyDataReader>(path));
    }
  for (const int mode : {0, 1, 2})
    for (const int compressor : {0, 1}) {
      SCOPED_TRACE(::testing::Message() << "xml mode " << mode << " compressor " << compressor);
      const std::string path = dir.file("surface.vtp");
      vtkNew<vtkXMLPolyDataWriter> writer;
      writer->SetFileName(path.c_str());
      writer->SetInputData(testSurface());
      if (mode == 0) writer->SetDataModeToAscii();
      if (mode == 1) writer->SetDataModeToBinary();
      if (mode == 2) writer->SetDataModeToAppended();
      writer->SetCompressorType(compressor);
      ASSERT_EQ(writer->Write(), 1);
      expectSameSurface(readSurface(path), referenceSurface<vtkXMLPolyDataReader>(path));
    }
}

TEST(VtkReaderEquivalence, StlAsciiAndBinaryWithSharedVertices) {
  TempDir dir;
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(testSurface());
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  triangulate->Update();
  for (const bool binary : {false, true}) {
    SCOPED_TRACE(::testing::Message() << "binary " << binary);
    const std::string path = dir.file("surface.stl");
    vtkNew<vtkSTLWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetInputData(triangulate->GetOutput());
    binary ? writer->SetFileTypeToBinary() : writer->SetFileTypeToASCII();
    ASSERT_EQ(writer->Write(), 1);
    expectSameSurface(readSurface(path), referenceSurface<vtkSTLReader>(path));
  }
}

TEST(VtkReaderEquivalence, SharedCylinderAndFineLiver) {
  SHARED_FILE_OR_SKIP(cylinder, "optimus-cylinder/cylinder3_770.vtk");
  expectSameTets(readTetMesh(cylinder), referenceTets(cylinder));
  SHARED_FILE_OR_SKIP(liver, "sofa-liver/liverFine.vtu");
  expectSameTets(readTetMesh(liver), referenceTets(liver));
}

TEST(VtkReaderEquivalence, SharedBinaryLiverSurface) {
  SHARED_FILE_OR_SKIP(path, "sofa-liver/liver.vtk");
  expectSameSurface(readSurface(path), referenceSurface<vtkPolyDataReader>(path));
}

}  // namespace
}  // namespace bcassim
