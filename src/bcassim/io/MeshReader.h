// Reading a tetrahedral mesh from .vtk (legacy), .vtu or .msh (Gmsh), validated and oriented.
// Coordinates are returned as stored: the files are expected in metres.
#pragma once
#include <string>

#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// Reads the tetrahedra of `path` (other cell types are ignored; nodes are kept in file order).
// Region ids come from the integer-valued cell array `regionField`; when it is empty, from the
// first of "dataset", "region", "gmsh:physical", "CellEntityIds" present, else all 0; arrays of
// any numeric type are accepted if their values are whole numbers. For .msh the region is the
// physical tag and `regionField` is not used. The mesh is checked by validateTetMesh(). Throws
// InputError with one line naming the file, e.g. "liver.vtu: cannot open file".
TetMesh readTetMesh(const std::string& path, const std::string& regionField = "");

}  // namespace bcassim
