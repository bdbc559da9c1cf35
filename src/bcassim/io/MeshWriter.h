// Writing meshes and point sets as VTK files for ParaView: tetrahedral meshes (.vtu, legacy .vtk)
// at given positions with named fields, and point clouds / line segments (.vtp). Metres.
#pragma once
#include <Eigen/Core>
#include <string>

#include "bcassim/io/FieldSet.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// Writes `mesh` to `path` (.vtu, or .vtk legacy binary), points at `positions` (3N node-major,
// metres; empty means the rest positions mesh.V), the region as the int cell field "region",
// and `fields`. Doubles are stored in binary so a read gives back the exact values. Creates the
// parent directory if missing. Throws InputError when the file cannot be written, and
// std::invalid_argument when a size does not match the mesh.
void writeTetMesh(const std::string& path, const TetMesh& mesh,
                  const Eigen::VectorXd& positions = Eigen::VectorXd(),
                  const FieldSet& fields = FieldSet());

// Writes `points` as a .vtp of vertex cells (one per point, so cell fields are per point too),
// e.g. markers or observed points.
void writePointCloud(const std::string& path, const Eigen::MatrixX3d& points,
                     const FieldSet& fields = FieldSet());

// Writes segments between `points` (row i of `segments` joins two point indices) as a .vtp of
// line cells, e.g. springs; cell fields have one value per segment.
void writePolyLines(const std::string& path, const Eigen::MatrixX3d& points,
                    const Eigen::MatrixX2i& segments, const FieldSet& fields = FieldSet());

// Writes ordered `points` as one polyline (.vtp of line cells joining consecutive points), e.g. a
// ligament curve; each point scalar of `pointFields` becomes a cell scalar too, the mean of the
// segment's two ends, so that ParaView can colour the line by it.
void writePolyline(const std::string& path, const Eigen::MatrixX3d& points,
                   const FieldSet& pointFields = FieldSet());

}  // namespace bcassim
