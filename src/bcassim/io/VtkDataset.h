// Internal to the io module: a VTK dataset as our bounded readers return it (legacy .vtk and XML
// .vtu/.vtp): points, cells with their types, and the cell data arrays, every cell already checked
// against its type and every point index against the points.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace bcassim::io {

// Cells as offsets into one connectivity list: cell c has the point ids
// connectivity[offsets[c]] .. connectivity[offsets[c + 1] - 1].
struct VtkCells {
  std::vector<long long> offsets{0};
  std::vector<int> connectivity;
  std::vector<unsigned char> types;  // VTK type of each cell (unstructured grids only)
  std::vector<int> lines;            // file line of each cell (ASCII legacy files), else empty

  long long size() const { return static_cast<long long>(offsets.size()) - 1; }
  long long count(long long c) const { return offsets[c + 1] - offsets[c]; }
};

struct VtkArray {
  std::string name;
  int components = 1;
  long long tuples = 0;
  bool numeric = true;         // false for string arrays, which are skipped
  std::vector<double> values;  // numeric arrays: tuples x components values, tuple after tuple
};

struct VtkDataset {
  enum class Kind { kUnstructuredGrid, kPolyData };
  Kind kind = Kind::kUnstructuredGrid;
  std::string source;                    // the file, for messages
  Eigen::MatrixX3d points;               // as stored (32-bit floats widened exactly)
  VtkCells cells;                        // unstructured grid cells
  VtkCells verts, lines, polys, strips;  // poly data cells, in VTK's cell order
  std::vector<VtkArray> cellArrays;      // cell data, in file order
  int cellsLine = 0;  // XML files: line of the element holding the cells (0: unknown)

  // Where cell c of `cells` is defined, for messages: "cube.vtk:12", "liver.vtu:40", "liver.vtk".
  std::string cellLocation(long long c) const;
  long long numCells() const {
    return kind == Kind::kUnstructuredGrid
               ? cells.size()
               : verts.size() + lines.size() + polys.size() + strips.size();
  }
};

}  // namespace bcassim::io
