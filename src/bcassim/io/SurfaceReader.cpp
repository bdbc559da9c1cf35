#include "bcassim/io/SurfaceReader.h"

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>
#include <vtkSTLWriter.h>
#include <vtkTriangleFilter.h>
#include <vtkXMLPolyDataWriter.h>

#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/LegacyVtkReader.h"
#include "bcassim/io/ObjFormat.h"
#include "bcassim/io/PlyReader.h"
#include "bcassim/io/StlReader.h"
#include "bcassim/io/TextLines.h"
#include "bcassim/io/VtkSupport.h"
#include "bcassim/io/VtkXmlReader.h"

namespace bcassim {
namespace {

TriMesh trianglesOf(vtkPolyData* input, const std::string& path) {
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(input);
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  triangulate->Update();
  vtkPolyData* out = triangulate->GetOutput();
  TriMesh mesh;
  mesh.V = io::pointsOf(input);
  std::vector<int> faces;
  vtkCellArray* polys = out->GetPolys();
  vtkNew<vtkIdList> ids;
  polys->InitTraversal();
  while (polys->GetNextCell(ids))
    if (ids->GetNumberOfIds() == 3)
      for (int k = 0; k < 3; ++k) faces.push_back(static_cast<int>(ids->GetId(k)));
  if (faces.empty())
    throw InputError(
        fmt::format("{}: no triangles or polygons among {} cells; expected a "
                    "surface",
                    path, input->GetNumberOfCells()));
  mesh.F = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      faces.data(), static_cast<Eigen::Index>(faces.size() / 3), 3);
  io::requireFinitePoints(mesh.V, path);
  return mesh;
}

vtkSmartPointer<vtkCellArray> toVtkCells(const io::VtkCells& cells) {
  auto out = vtkSmartPointer<vtkCellArray>::New();
  std::vector<vtkIdType> ids;
  for (long long c = 0; c < cells.size(); ++c) {
    ids.assign(cells.connectivity.begin() + cells.offsets[c],
               cells.connectivity.begin() + cells.offsets[c + 1]);
    out->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  return out;
}

// Poly data read (and checked) by our own readers, triangulated by VTK's filter as before.
TriMesh readPolyData(const io::VtkDataset& data) {
  if (data.points.rows() == 0)
    throw InputError(fmt::format("{}: no points; expected a surface", data.source));
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(io::toVtkPoints(data.points));
  poly->SetVerts(toVtkCells(data.verts));
  poly->SetLines(toVtkCells(data.lines));
  poly->SetPolys(toVtkCells(data.polys));
  poly->SetStrips(toVtkCells(data.strips));
  io::VtkErrorCapture capture;
  TriMesh mesh = trianglesOf(poly, data.source);
  io::throwIfVtkError(capture, data.source, "cannot triangulate the surface");
  return mesh;
}

vtkSmartPointer<vtkPolyData> toPolyData(const TriMesh& mesh) {
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(io::toVtkPoints(mesh.V));
  vtkNew<vtkCellArray> polys;
  for (Eigen::Index t = 0; t < mesh.F.rows(); ++t) {
    const vtkIdType ids[3] = {mesh.F(t, 0), mesh.F(t, 1), mesh.F(t, 2)};
    polys->InsertNextCell(3, ids);
  }
  data->SetPolys(polys);
  return data;
}

template <class Writer>
void writeVtkSurface(const std::string& path, const TriMesh& mesh, bool binary) {
  io::createParentDirectory(path);
  const auto data = toPolyData(mesh);
  io::VtkErrorCapture capture;
  vtkNew<Writer> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(data);
  if (binary) writer->SetFileTypeToBinary();
  const int ok = writer->Write();
  io::throwIfVtkWriteError(capture, path);
  if (!ok) throw OutputError(fmt::format("{}: cannot write file", path));
}

TriMesh readPlySurface(const std::string& path) {
  io::PlyContents ply = io::readPly(path);
  if (ply.F.rows() == 0)
    throw InputError(fmt::format(
        "{}: no faces ({} vertices); expected a surface (a 'face' element with vertex_indices)",
        path, ply.V.rows()));
  io::requireFinitePoints(ply.V, path);
  TriMesh mesh;
  mesh.V = std::move(ply.V);
  mesh.F = std::move(ply.F);
  return mesh;
}

}  // namespace

TriMesh readSurface(const std::string& path) {
  const std::string ext = io::lowerExtension(path);
  if (ext != ".stl" && ext != ".obj" && ext != ".ply" && ext != ".vtk" && ext != ".vtp")
    throw InputError(
        fmt::format("{}: unsupported surface format '{}'; expected .stl, .obj, .ply, .vtk "
                    "or .vtp",
                    path, ext));
  io::requireReadableFile(path);
  if (ext == ".obj") return readObj(path);
  if (ext == ".ply") return readPlySurface(path);
  if (ext == ".stl") return io::readStl(path);
  const auto kind = io::VtkDataset::Kind::kPolyData;
  return readPolyData(ext == ".vtp" ? io::readVtkXml(path, kind) : io::readLegacyVtk(path, kind));
}

void writeSurface(const std::string& path, const TriMesh& mesh) {
  const std::string ext = io::lowerExtension(path);
  if (ext == ".obj") return writeObj(path, mesh);
  if (ext == ".stl") return writeVtkSurface<vtkSTLWriter>(path, mesh, true);
  if (ext == ".vtk") return writeVtkSurface<vtkPolyDataWriter>(path, mesh, true);
  if (ext == ".vtp") {
    io::createParentDirectory(path);
    const auto data = toPolyData(mesh);
    io::VtkErrorCapture capture;
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetInputData(data);
    writer->SetDataModeToBinary();
    const int ok = writer->Write();
    io::throwIfVtkWriteError(capture, path);
    if (!ok) throw OutputError(fmt::format("{}: cannot write file", path));
    return;
  }
  throw InputError(
      fmt::format("{}: unsupported surface output format '{}'; expected .stl, .obj, "
                  ".vtk or .vtp",
                  path, ext));
}

}  // namespace bcassim
