// Internal to the io module: STL surfaces (ASCII or binary) read by a bounded reader of our own,
// giving the same mesh as VTK's vtkSTLReader (coincident vertices merged in first-seen order,
// triangles left degenerate by the merge dropped).
#pragma once
#include <string>

#include "bcassim/mesh/TriMesh.h"

namespace bcassim::io {

// A binary file (80-byte header, triangle count, 50 bytes per triangle) must be exactly as long as
// its count says; an ASCII file ("solid" ... "endsolid") must follow the grammar line by line.
// Every coordinate must be a finite 32-bit float. Throws InputError naming the file and the line
// (ASCII) or triangle (binary), e.g. "part.stl:7: expected 'vertex x y z', got 'endloop'".
TriMesh readStl(const std::string& path);

}  // namespace bcassim::io
