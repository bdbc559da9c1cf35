// VTK's cell type numbers (vtkCellType.h): name, dimension and point count of each, so that the
// VTK readers can check every cell's point count against its type before anything uses it.
#pragma once
#include <string>

namespace bcassim::io {

constexpr int kVtkTetra = 10;

struct VtkCellType {
  int id;
  const char* name;
  int dimension;  // 0 point, 1 curve, 2 surface, 3 volume
  int points;     // fixed point count; 0 when the count varies (polygon, polyline, ...)
  int minPoints;  // least point count of a variable-size cell
};

// The type numbered `id`, or nullptr when VTK has no such type (or it has no point list, as the
// empty cell).
const VtkCellType* findVtkCellType(long long id);

// Empty when a cell of `type` may have `count` points, else what it needs: "8", "at least 3".
std::string vtkCellCountExpectation(const VtkCellType& type, long long count);

// "hexahedron, VTK type 12", for messages.
std::string describeVtkCellType(const VtkCellType& type);

}  // namespace bcassim::io
