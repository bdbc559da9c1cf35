// Reading a tetrahedral mesh from .vtk (legacy), .vtu or .msh (Gmsh), validated and oriented.
// Coordinates are returned as stored: the files are expected in metres.
#pragma once
#include <string>

#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// Reads the tetrahedra of `path` (nodes are kept in file order). Cells of lower dimension
// (triangles, lines, points) are ignored; other volume cells (hexahedra, wedges, quadratic tets)
// are refused, as are cells whose point count does not fit their type. The files are parsed by our
// own bounded readers (io/LegacyVtkReader.h, io/VtkXmlReader.h, io/GmshReader.h), never by VTK's.
// Region ids come from the integer-valued cell array `regionField`; when it is empty, from the
// first of "dataset", "region", "gmsh:physical", "CellEntityIds" present, else all 0; arrays of
// any numeric type are accepted if their values are whole numbers. For .msh the region is the
// physical tag and `regionField` is not used. The mesh is checked by validateTetMesh(), which
// names nodes and tets as the file does (Gmsh tags, VTK point and cell numbers) with their line.
// Throws InputError with one line naming the file, e.g. "liver.vtu: cannot open file".
TetMesh readTetMesh(const std::string& path, const std::string& regionField = "");

}  // namespace bcassim
