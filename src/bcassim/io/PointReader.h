// Reading a set of points, e.g. observed points, markers or a point cloud: the points of any VTK
// dataset (.vtk, .vtu, .vtp), the vertices of a PLY file (.ply, as RGB-D tools write clouds), the
// rows of a CSV file, the lines of a text file (x y z) or an N x 3 NumPy array (.npy).
// Coordinates are as stored (metres expected).
#pragma once
#include <Eigen/Core>
#include <string>

namespace bcassim {

// VTK files: all points in file order, whatever the cells. CSV: columns x,y,z named in a header
// (other columns ignored) or, without a header, exactly 3 columns. .txt: three whitespace
// separated numbers per line; blank lines and '#' comments (to the end of a line) are skipped.
// .npy: a float or integer array of shape (N, 3), N >= 1. .ply: every vertex (io/PlyReader), its
// faces ignored. Every coordinate must be finite.
// Throws InputError naming the file (and line or entry), e.g. "pc.txt:7: expected 3 numbers
// (x y z), got 2".
Eigen::MatrixX3d readPoints(const std::string& path);

}  // namespace bcassim
