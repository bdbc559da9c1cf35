// Named data arrays to attach to a written dataset (ParaView output): point scalars and vectors,
// and cell scalars. Values are in SI units; the name should say which (e.g. "stress_Pa").
#pragma once
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

namespace bcassim {
struct FieldSet {
  std::vector<std::pair<std::string, Eigen::VectorXd>> pointScalars;   // one value per point
  std::vector<std::pair<std::string, Eigen::MatrixX3d>> pointVectors;  // one row per point
  std::vector<std::pair<std::string, Eigen::VectorXd>> cellScalars;    // one value per cell
};
}  // namespace bcassim
