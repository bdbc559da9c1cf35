#include "bcassim/io/MeshReader.h"

#include <fmt/format.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <limits>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/GmshReader.h"
#include "bcassim/io/TextLines.h"
#include "bcassim/io/VtkSupport.h"
#include "bcassim/mesh/MeshValidation.h"

namespace bcassim {
namespace {

vtkDataArray* regionArray(vtkUnstructuredGrid* grid, const std::string& path,
                          const std::string& regionField) {
  vtkCellData* cd = grid->GetCellData();
  if (!regionField.empty()) {
    if (vtkDataArray* a = cd->GetArray(regionField.c_str())) return a;
    std::string names;
    for (int i = 0; i < cd->GetNumberOfArrays(); ++i)
      names += fmt::format("{}'{}'", names.empty() ? "" : ", ",
                           cd->GetArrayName(i) ? cd->GetArrayName(i) : "");
    throw InputError(fmt::format("{}: no numeric cell field '{}'; the file has {}", path,
                                 regionField, names.empty() ? "no cell fields" : names));
  }
  for (const char* name : {"dataset", "region", "gmsh:physical", "CellEntityIds"})
    if (vtkDataArray* a = cd->GetArray(name)) return a;
  return nullptr;
}

TetMesh tetsOf(vtkUnstructuredGrid* grid, const std::string& path, const std::string& regionField) {
  TetMesh mesh;
  mesh.V = io::pointsOf(grid);
  std::vector<vtkIdType> tetCells;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    if (grid->GetCellType(c) == VTK_TETRA) tetCells.push_back(c);
  if (tetCells.empty())
    throw InputError(
        fmt::format("{}: no tetrahedra (VTK_TETRA cells) among {} cells; expected a "
                    "volume mesh",
                    path, grid->GetNumberOfCells()));
  const Eigen::Index nt = static_cast<Eigen::Index>(tetCells.size());
  mesh.T.resize(nt, 4);
  vtkNew<vtkIdList> ids;
  for (Eigen::Index t = 0; t < nt; ++t) {
    grid->GetCellPoints(tetCells[t], ids);
    for (int k = 0; k < 4; ++k) mesh.T(t, k) = static_cast<int>(ids->GetId(k));
  }
  if (vtkDataArray* regions = regionArray(grid, path, regionField)) {
    const char* name = regions->GetName();
    if (regions->GetNumberOfComponents() != 1)
      throw InputError(
          fmt::format("{}: cell field '{}' has {} components; expected 1 region id "
                      "per cell",
                      path, name, regions->GetNumberOfComponents()));
    mesh.region.resize(nt);
    for (Eigen::Index t = 0; t < nt; ++t) {
      // Region fields are often stored as floats (e.g. "SCALARS dataset float"); accept any
      // type whose values are whole numbers.
      const double v = regions->GetTuple1(tetCells[t]);
      if (!(std::abs(v) <= std::numeric_limits<int>::max()) || v != std::round(v))
        throw InputError(
            fmt::format("{}: cell field '{}' has value {} at cell {}; expected an "
                        "integer region id",
                        path, name, v, tetCells[t]));
      mesh.region(t) = static_cast<int>(v);
    }
  }
  return mesh;
}

TetMesh readLegacyVtk(const std::string& path, const std::string& regionField) {
  io::VtkErrorCapture capture;
  vtkNew<vtkUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  if (!reader->IsFileUnstructuredGrid()) {
    io::throwIfVtkError(capture, path, "cannot read legacy VTK file");
    throw InputError(
        fmt::format("{}: not a legacy VTK unstructured grid; expected 'DATASET "
                    "UNSTRUCTURED_GRID' with tetrahedra",
                    path));
  }
  reader->Update();
  io::throwIfLegacyVtkError(capture, path, "cannot read legacy VTK file");
  vtkUnstructuredGrid* grid = reader->GetOutput();
  if (!grid || grid->GetNumberOfPoints() == 0)
    throw InputError(
        fmt::format("{}: no points read; expected a legacy VTK unstructured grid", path));
  return tetsOf(grid, path, regionField);
}

TetMesh readVtu(const std::string& path, const std::string& regionField) {
  io::VtkErrorCapture capture;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  if (!reader->CanReadFile(path.c_str())) {
    io::throwIfVtkError(capture, path, "cannot read VTK XML file");
    throw InputError(
        fmt::format("{}: not a VTK XML unstructured grid; expected <VTKFile "
                    "type=\"UnstructuredGrid\">",
                    path));
  }
  reader->SetFileName(path.c_str());
  reader->Update();
  io::throwIfVtkError(capture, path, "cannot read VTK XML file");
  vtkUnstructuredGrid* grid = reader->GetOutput();
  if (!grid || grid->GetNumberOfPoints() == 0)
    throw InputError(fmt::format("{}: no points read; expected a VTK XML unstructured grid", path));
  return tetsOf(grid, path, regionField);
}

}  // namespace

TetMesh readTetMesh(const std::string& path, const std::string& regionField) {
  const std::string ext = io::lowerExtension(path);
  if (ext != ".vtk" && ext != ".vtu" && ext != ".msh")
    throw InputError(
        fmt::format("{}: unsupported tetrahedral mesh format '{}'; expected .vtk, "
                    ".vtu or .msh",
                    path, ext));
  io::requireReadableFile(path);
  TetMesh mesh = ext == ".msh"   ? readGmshTetMesh(path)
                 : ext == ".vtu" ? readVtu(path, regionField)
                                 : readLegacyVtk(path, regionField);
  validateTetMesh(mesh, path);
  return mesh;
}

}  // namespace bcassim
