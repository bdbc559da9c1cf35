// Reader of ASCII Medit meshes (.mesh: MMG, CGAL's Mesh_3, TetGen -g, Gmsh write them): the
// tetrahedra with their reference as region. Coordinates are returned as stored.
#pragma once
#include <string>

#include "bcassim/mesh/MeshValidation.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// The file is a stream of keywords and numbers ('#' starts a comment): MeshVersionFormatted,
// Dimension 3, then sections (Vertices: x y z ref; Tetrahedra: four 1-based vertex numbers and a
// ref; the other usual sections, Triangles, Edges, Corners, Ridges, Normals..., are skipped) up
// to End. Vertices are kept in file order, including vertices no tetrahedron uses. The mesh is
// not validated: readTetMesh() is the entry point that also checks it. Throws InputError naming
// file and line, e.g. "liver.mesh:57: tetrahedron 3 names vertex 0; expected 1 to 8 (Medit
// numbers vertices from 1)". `origin`, when given, receives the lines for validateTetMesh().
TetMesh readMeditTetMesh(const std::string& path, MeshOrigin* origin = nullptr);

}  // namespace bcassim
