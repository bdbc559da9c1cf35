// Writing point sets as CSV for users and scripts: columns x,y,z (m) and optional named scalar
// columns, one row per point, at round-trip precision (17 significant digits), so that a file
// read back gives the same doubles; several sets in one file carry a leading set-index column.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace bcassim {

struct NamedColumn {
  std::string name;
  Eigen::VectorXd values;  // one per point
};

// Writes `path` (parent folders created): header "x,y,z[,extra names]". Throws InputError naming
// the path and the reason when it cannot be written, std::invalid_argument when a column's length
// differs from the number of points.
void writePointsCsv(const std::string& path, const Eigen::MatrixX3d& points,
                    const std::vector<NamedColumn>& extra = {});

// Several point sets in one file: header "<setColumn>,x,y,z", the set's index in the first column.
void writePointSetsCsv(const std::string& path, const std::string& setColumn,
                       const std::vector<Eigen::MatrixX3d>& sets);

}  // namespace bcassim
