#include "bcassim/io/MeshReader.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/GmshReader.h"
#include "bcassim/io/LegacyVtkReader.h"
#include "bcassim/io/MeditReader.h"
#include "bcassim/io/TextLines.h"
#include "bcassim/io/VtkCellTypes.h"
#include "bcassim/io/VtkXmlReader.h"
#include "bcassim/mesh/MeshValidation.h"

namespace bcassim {
namespace {

const io::VtkArray* regionArray(const io::VtkDataset& data, const std::string& regionField) {
  const auto named = [&](const std::string& name) -> const io::VtkArray* {
    for (const io::VtkArray& a : data.cellArrays)
      if (a.numeric && a.name == name) return &a;
    return nullptr;
  };
  if (!regionField.empty()) {
    if (const io::VtkArray* a = named(regionField)) return a;
    std::string names;
    for (const io::VtkArray& a : data.cellArrays)
      names += fmt::format("{}'{}'", names.empty() ? "" : ", ", io::excerpt(a.name));
    throw InputError(fmt::format("{}: no numeric cell field '{}'; the file has {}", data.source,
                                 io::excerpt(regionField),
                                 names.empty() ? "no cell fields" : names));
  }
  for (const char* name : {"dataset", "region", "gmsh:physical", "CellEntityIds"})
    if (const io::VtkArray* a = named(name)) return a;
  return nullptr;
}

// The linear tetrahedra of a VTK unstructured grid. Cells of lower dimension (boundary triangles,
// lines) are ignored; other volume cells would leave holes, so they are refused.
TetMesh tetsOf(io::VtkDataset&& data, const std::string& regionField, MeshOrigin& origin) {
  const io::VtkCells& cells = data.cells;
  std::vector<long long> tetCells;
  for (long long c = 0; c < cells.size(); ++c) {
    if (cells.types[c] == io::kVtkTetra) {
      tetCells.push_back(c);
      continue;
    }
    const io::VtkCellType& type = *io::findVtkCellType(cells.types[c]);
    if (type.dimension == 3)
      throw InputError(fmt::format(
          "{}: cell {} is a {} (VTK type {}); expected linear tetrahedra (VTK type {}), the only "
          "volume cells supported",
          data.cellLocation(c), c, type.name, type.id, io::kVtkTetra));
  }
  if (tetCells.empty())
    throw InputError(
        fmt::format("{}: no tetrahedra (VTK_TETRA cells) among {} cells; expected a volume mesh",
                    data.source, cells.size()));
  TetMesh mesh;
  mesh.V = std::move(data.points);
  const Eigen::Index nt = static_cast<Eigen::Index>(tetCells.size());
  mesh.T.resize(nt, 4);
  origin.source = data.source;
  origin.nodeWord = "point";
  origin.tetWord = "cell";
  origin.tetNumbers = tetCells;
  for (Eigen::Index t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) mesh.T(t, k) = cells.connectivity[cells.offsets[tetCells[t]] + k];
    if (!cells.lines.empty()) origin.tetLines.push_back(cells.lines[tetCells[t]]);
  }
  if (const io::VtkArray* regions = regionArray(data, regionField)) {
    const std::string name = io::excerpt(regions->name);
    if (regions->components != 1)
      throw InputError(
          fmt::format("{}: cell field '{}' has {} components; expected 1 region id per cell",
                      data.source, name, regions->components));
    if (regions->tuples != cells.size())
      throw InputError(fmt::format("{}: cell field '{}' has {} values; expected one per cell ({})",
                                   data.source, name, regions->tuples, cells.size()));
    mesh.region.resize(nt);
    for (Eigen::Index t = 0; t < nt; ++t) {
      // Region fields are often stored as floats (e.g. "SCALARS dataset float"); accept any
      // type whose values are whole numbers.
      const double v = regions->values[tetCells[t]];
      if (!(std::abs(v) <= std::numeric_limits<int>::max()) || v != std::round(v))
        throw InputError(fmt::format(
            "{}: cell field '{}' has value {} at cell {}; expected an integer region id",
            data.source, name, v, tetCells[t]));
      mesh.region(t) = static_cast<int>(v);
    }
  }
  return mesh;
}

}  // namespace

TetMesh readTetMesh(const std::string& path, const std::string& regionField) {
  const std::string ext = io::lowerExtension(path);
  if (ext == ".meshb")
    throw InputError(fmt::format(
        "{}: binary Medit files are not supported; expected an ASCII .mesh (e.g. saved by MMG "
        "or Gmsh as .mesh)",
        path));
  if (ext != ".vtk" && ext != ".vtu" && ext != ".msh" && ext != ".mesh")
    throw InputError(fmt::format(
        "{}: unsupported tetrahedral mesh format '{}'; expected .vtk, .vtu, .msh or .mesh", path,
        io::excerpt(ext)));
  io::requireReadableFile(path);
  MeshOrigin origin;
  TetMesh mesh;
  if (ext == ".msh") {
    mesh = readGmshTetMesh(path, &origin);
  } else if (ext == ".mesh") {
    mesh = readMeditTetMesh(path, &origin);
  } else {
    const auto grid = io::VtkDataset::Kind::kUnstructuredGrid;
    mesh = tetsOf(ext == ".vtu" ? io::readVtkXml(path, grid) : io::readLegacyVtk(path, grid),
                  regionField, origin);
  }
  validateTetMesh(mesh, origin);
  return mesh;
}

}  // namespace bcassim
