// Basic numeric types shared by every module: Eigen aliases for 3-D mechanics.
// Positions of N nodes are stored node-major in a VectorXd of size 3N: (x0,y0,z0,x1,...).
#pragma once
#include <Eigen/Core>
#include <Eigen/Sparse>

namespace bcassim {
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat3 = Eigen::Matrix3d;
using Mat9 =
    Eigen::Matrix<double, 9, 9>;  // d vec(P) / d vec(F), vec() column-major as Eigen stores
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// View of node i of a node-major 3N vector.
inline auto node(Eigen::VectorXd& x, Eigen::Index i) { return x.segment<3>(3 * i); }
inline auto node(const Eigen::VectorXd& x, Eigen::Index i) { return x.segment<3>(3 * i); }
}  // namespace bcassim
