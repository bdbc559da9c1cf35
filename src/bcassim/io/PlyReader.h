// Internal to the io module: Stanford PLY files (ASCII, binary little- and big-endian), as RGB-D
// and stereo tools, 3D Slicer and MeshLab write them, read by a bounded reader of our own: the
// vertices' x, y, z and the faces' vertex lists; every other element and property is skipped.
#pragma once
#include <Eigen/Core>
#include <string>

namespace bcassim::io {

struct PlyContents {
  Eigen::MatrixX3d V;  // every vertex's x, y, z in file order, as stored (may be non-finite)
  Eigen::MatrixX3i F;  // the faces as triangles, a polygon fanned from its first vertex; none
                       // without a face element
};

// The header must start with "ply" and a format line, declare its elements and properties (types
// char/int8 ... double/float64, lists for the faces' `vertex_indices` or `vertex_index`) and end
// with "end_header"; the data must hold exactly what it declares. A vertex element with scalar
// properties x, y and z is required. A face needs at least 3 vertices, each an index below the
// vertex count. Throws InputError naming the file and the header line, the data line (ASCII) or
// the element and its index (binary), e.g. "cloud.ply:14: vertex 3: property 'y' is 'abc';
// expected a number".
PlyContents readPly(const std::string& path);

}  // namespace bcassim::io
