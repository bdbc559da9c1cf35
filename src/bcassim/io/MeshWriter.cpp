#include "bcassim/io/MeshWriter.h"

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridWriter.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/VtkSupport.h"

namespace bcassim {
namespace {

void writePolyData(const std::string& path, vtkPolyData* data) {
  const std::string ext = io::lowerExtension(path);
  if (ext != ".vtp")
    throw InputError(
        fmt::format("{}: unsupported point set format '{}'; expected .vtp", path, ext));
  io::createParentDirectory(path);
  io::VtkErrorCapture capture;
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(data);
  writer->SetDataModeToBinary();
  const int ok = writer->Write();
  io::throwIfVtkWriteError(capture, path);
  if (!ok) throw OutputError(fmt::format("{}: cannot write file", path));
}

}  // namespace

void writeTetMesh(const std::string& path, const TetMesh& mesh, const Eigen::VectorXd& positions,
                  const FieldSet& fields) {
  const std::string ext = io::lowerExtension(path);
  if (ext != ".vtu" && ext != ".vtk")
    throw InputError(
        fmt::format("{}: unsupported tetrahedral mesh output format '{}'; expected "
                    ".vtu or .vtk",
                    path, ext));
  const Eigen::Index n = mesh.numNodes();
  if (positions.size() != 0 && positions.size() != 3 * n)
    throw std::invalid_argument(
        fmt::format("writeTetMesh({}): {} position values for {} nodes; "
                    "expected {}",
                    path, positions.size(), n, 3 * n));
  if (mesh.region.size() != 0 && mesh.region.size() != mesh.numTets())
    throw std::invalid_argument(fmt::format("writeTetMesh({}): {} region ids for {} tets", path,
                                            mesh.region.size(), mesh.numTets()));

  vtkNew<vtkUnstructuredGrid> grid;
  if (positions.size() == 0) {
    grid->SetPoints(io::toVtkPoints(mesh.V));
  } else {
    grid->SetPoints(
        io::toVtkPoints(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
            positions.data(), n, 3)));
  }
  grid->Allocate(mesh.numTets());
  vtkIdType ids[4];
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    for (int k = 0; k < 4; ++k) ids[k] = mesh.T(t, k);
    grid->InsertNextCell(VTK_TETRA, 4, ids);
  }
  vtkNew<vtkIntArray> region;
  region->SetName("region");
  region->SetNumberOfValues(mesh.numTets());
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) region->SetValue(t, mesh.regionOf(t));
  grid->GetCellData()->AddArray(region);
  io::attachFields(grid, fields);

  io::createParentDirectory(path);
  io::VtkErrorCapture capture;
  int ok = 0;
  if (ext == ".vtu") {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetInputData(grid);
    writer->SetDataModeToBinary();
    ok = writer->Write();
  } else {
    vtkNew<vtkUnstructuredGridWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetInputData(grid);
    writer->SetFileTypeToBinary();
    ok = writer->Write();
  }
  io::throwIfVtkWriteError(capture, path);
  if (!ok) throw OutputError(fmt::format("{}: cannot write file", path));
}

void writePointCloud(const std::string& path, const Eigen::MatrixX3d& points,
                     const FieldSet& fields) {
  vtkNew<vtkPolyData> data;
  data->SetPoints(io::toVtkPoints(points));
  vtkNew<vtkCellArray> verts;
  for (vtkIdType i = 0; i < points.rows(); ++i) verts->InsertNextCell(1, &i);
  data->SetVerts(verts);
  io::attachFields(data, fields);
  writePolyData(path, data);
}

void writePolyLines(const std::string& path, const Eigen::MatrixX3d& points,
                    const Eigen::MatrixX2i& segments, const FieldSet& fields) {
  for (Eigen::Index s = 0; s < segments.rows(); ++s)
    for (int k = 0; k < 2; ++k)
      if (segments(s, k) < 0 || segments(s, k) >= points.rows())
        throw std::invalid_argument(
            fmt::format("writePolyLines({}): segment {} refers to point "
                        "{}; expected an index in [0, {})",
                        path, s, segments(s, k), points.rows()));
  vtkNew<vtkPolyData> data;
  data->SetPoints(io::toVtkPoints(points));
  vtkNew<vtkCellArray> lines;
  for (Eigen::Index s = 0; s < segments.rows(); ++s) {
    const vtkIdType ids[2] = {segments(s, 0), segments(s, 1)};
    lines->InsertNextCell(2, ids);
  }
  data->SetLines(lines);
  io::attachFields(data, fields);
  writePolyData(path, data);
}

void writePolyline(const std::string& path, const Eigen::MatrixX3d& points,
                   const FieldSet& pointFields) {
  Eigen::MatrixX2i segments(std::max<Eigen::Index>(0, points.rows() - 1), 2);
  for (Eigen::Index i = 0; i < segments.rows(); ++i)
    segments.row(i) << static_cast<int>(i), static_cast<int>(i + 1);
  FieldSet cells;
  for (const auto& [name, v] : pointFields.pointScalars) {
    Eigen::VectorXd c(segments.rows());
    for (Eigen::Index i = 0; i < segments.rows(); ++i) c(i) = 0.5 * (v(i) + v(i + 1));
    cells.cellScalars.push_back({name, c});
  }
  writePolyLines(path, points, segments, cells);
}

}  // namespace bcassim
