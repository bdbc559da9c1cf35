// Reading a set of points, e.g. observed points or markers: the points of any VTK dataset
// (.vtk, .vtu, .vtp) or the rows of a CSV file. Coordinates are as stored (metres expected).
#pragma once
#include <Eigen/Core>
#include <string>

namespace bcassim {

// VTK files: all points in file order, whatever the cells. CSV: columns x,y,z named in a header
// (other columns ignored) or, without a header, exactly 3 columns. Throws InputError.
Eigen::MatrixX3d readPoints(const std::string& path);

}  // namespace bcassim
