// Reader of ASCII Gmsh meshes (.msh formats 1, 2.x and 4.1): the tetrahedra (element type 4) with
// their physical tag as region. Coordinates are returned as stored (metres if the file is).
#pragma once
#include <string>

#include "bcassim/mesh/MeshValidation.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// Nodes are kept in $Nodes order, including nodes no tetrahedron uses; other element types are
// ignored. Region is the physical tag (0 when the element has none). The mesh is not validated:
// readTetMesh() is the entry point that also checks it. Throws InputError naming file and line,
// e.g. "mesh.msh:57: expected 8 fields in an element line, got 6". Binary files are rejected.
// `origin`, when given, receives the node and element tags and lines for validateTetMesh().
TetMesh readGmshTetMesh(const std::string& path, MeshOrigin* origin = nullptr);

}  // namespace bcassim
