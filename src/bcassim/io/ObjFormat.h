// Wavefront OBJ triangle surfaces: a reader of vertices and faces (polygons fan-triangulated) and
// a writer. Coordinates are as stored in the file; OBJ carries no unit.
#pragma once
#include <string>

#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// Reads "v x y z [w]" and "f" lines ("a", "a/b", "a//c", "a/b/c" vertex forms; 1-based or
// negative, i.e. relative, indices); every other statement (vn, vt, o, g, s, usemtl, ...) is
// ignored. Throws InputError naming file and line, e.g. "liver.obj:12: face refers to vertex 40,
// but the file defines 39 vertices".
TriMesh readObj(const std::string& path);

// Writes vertices with round-trip precision and 1-based faces.
void writeObj(const std::string& path, const TriMesh& mesh);

}  // namespace bcassim
