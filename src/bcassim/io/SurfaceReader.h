// Reading and writing triangle surfaces: .stl, .obj, .vtk (legacy polydata), .vtp.
// Coordinates are as stored (the shared livers/*.obj are in millimetres: scale before use).
#pragma once
#include <string>

#include "bcassim/io/PointReader.h"  // readPoints, for observed point sets read with surfaces
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// Reads the triangles of a surface; polygons and strips are triangulated, other cells ignored.
// STL vertices shared by triangles are merged. The files are parsed by our own bounded readers
// (io/StlReader.h, io/LegacyVtkReader.h, io/VtkXmlReader.h, io/ObjFormat.h); VTK only
// triangulates polygons and strips. Throws InputError with one line naming the file.
TriMesh readSurface(const std::string& path);

// Writes .vtp, .vtk (binary, exact doubles), .obj (round-trip decimal) or .stl (binary, so
// coordinates are rounded to float). Creates the parent directory if missing.
void writeSurface(const std::string& path, const TriMesh& mesh);

}  // namespace bcassim
