#include "bcassim/io/VtkCellTypes.h"

#include <fmt/format.h>

namespace bcassim::io {
namespace {

// From vtkCellType.h (VTK 9.1). The parametric and "higher order" placeholders (51-67) have no
// file representation and are left out, so that a file using them is refused by name.
constexpr VtkCellType kTypes[] = {
    {1, "vertex", 0, 1, 1},
    {2, "poly-vertex", 0, 0, 1},
    {3, "line", 1, 2, 2},
    {4, "polyline", 1, 0, 2},
    {5, "triangle", 2, 3, 3},
    {6, "triangle strip", 2, 0, 3},
    {7, "polygon", 2, 0, 3},
    {8, "pixel", 2, 4, 4},
    {9, "quad", 2, 4, 4},
    {10, "tetrahedron", 3, 4, 4},
    {11, "voxel", 3, 8, 8},
    {12, "hexahedron", 3, 8, 8},
    {13, "wedge", 3, 6, 6},
    {14, "pyramid", 3, 5, 5},
    {15, "pentagonal prism", 3, 10, 10},
    {16, "hexagonal prism", 3, 12, 12},
    {21, "quadratic edge", 1, 3, 3},
    {22, "quadratic triangle", 2, 6, 6},
    {23, "quadratic quad", 2, 8, 8},
    {24, "quadratic tetrahedron", 3, 10, 10},
    {25, "quadratic hexahedron", 3, 20, 20},
    {26, "quadratic wedge", 3, 15, 15},
    {27, "quadratic pyramid", 3, 13, 13},
    {28, "biquadratic quad", 2, 9, 9},
    {29, "triquadratic hexahedron", 3, 27, 27},
    {30, "quadratic-linear quad", 2, 6, 6},
    {31, "quadratic-linear wedge", 3, 12, 12},
    {32, "biquadratic-quadratic wedge", 3, 18, 18},
    {33, "biquadratic-quadratic hexahedron", 3, 24, 24},
    {34, "biquadratic triangle", 2, 7, 7},
    {35, "cubic line", 1, 4, 4},
    {36, "quadratic polygon", 2, 0, 6},
    {37, "triquadratic pyramid", 3, 19, 19},
    {41, "convex point set", 3, 0, 4},
    {42, "polyhedron", 3, 0, 4},
    {68, "Lagrange curve", 1, 0, 2},
    {69, "Lagrange triangle", 2, 0, 3},
    {70, "Lagrange quadrilateral", 2, 0, 4},
    {71, "Lagrange tetrahedron", 3, 0, 4},
    {72, "Lagrange hexahedron", 3, 0, 8},
    {73, "Lagrange wedge", 3, 0, 6},
    {74, "Lagrange pyramid", 3, 0, 5},
    {75, "Bezier curve", 1, 0, 2},
    {76, "Bezier triangle", 2, 0, 3},
    {77, "Bezier quadrilateral", 2, 0, 4},
    {78, "Bezier tetrahedron", 3, 0, 4},
    {79, "Bezier hexahedron", 3, 0, 8},
    {80, "Bezier wedge", 3, 0, 6},
    {81, "Bezier pyramid", 3, 0, 5},
};

}  // namespace

const VtkCellType* findVtkCellType(long long id) {
  for (const VtkCellType& type : kTypes)
    if (type.id == id) return &type;
  return nullptr;
}

std::string vtkCellCountExpectation(const VtkCellType& type, long long count) {
  if (type.points > 0) return count == type.points ? std::string() : fmt::format("{}", type.points);
  return count >= type.minPoints ? std::string() : fmt::format("at least {}", type.minPoints);
}

std::string describeVtkCellType(const VtkCellType& type) {
  return fmt::format("{}, VTK type {}", type.name, type.id);
}

}  // namespace bcassim::io
