// Node positions between NumPy and the library: Python passes #V x 3 arrays (or flat 3N vectors),
// the library works on 3N node-major vectors. One copy each way, no more.
#pragma once
#include <pybind11/eigen.h>

#include <Eigen/Core>
#include <string>

namespace bcassim::python {

using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// A 3N vector from `x`: #nodes x 3 or 3 #nodes entries. Throws ValueError naming `what`.
inline Eigen::VectorXd flatPositions(const pybind11::array_t<double, pybind11::array::forcecast>& x,
                                     Eigen::Index nodes, const std::string& what) {
  const bool matrix = x.ndim() == 2 && x.shape(0) == nodes && x.shape(1) == 3;
  const bool flat = x.ndim() == 1 && x.shape(0) == 3 * nodes;
  if (!matrix && !flat)
    throw pybind11::value_error(what + ": expected " + std::to_string(nodes) + " x 3 or " +
                                std::to_string(3 * nodes) + " values (m)");
  const auto c =
      pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast>(x);
  return Eigen::Map<const Eigen::VectorXd>(c.data(), 3 * nodes);
}

// #nodes x 3 rows of a 3N node-major vector.
inline RowMatrixX3d nodeRows(const Eigen::VectorXd& x) {
  return Eigen::Map<const RowMatrixX3d>(x.data(), x.size() / 3, 3);
}

}  // namespace bcassim::python
