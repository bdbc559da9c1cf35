// A rigid motion x -> R x + t of points in metres: the result of rigid registration (Kabsch,
// ICP) shared by the atlas' pre-alignment and the tracking room's registration.
#pragma once
#include <Eigen/Core>

namespace bcassim {

struct RigidTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // m
  // Rows of P (#P by 3) mapped: R p + t.
  Eigen::MatrixX3d apply(const Eigen::MatrixX3d& P) const;
  // The motion undoing this one: R^T (x - t).
  RigidTransform inverse() const;
};

// `second` after `first`: x -> second(first(x)).
RigidTransform compose(const RigidTransform& second, const RigidTransform& first);

}  // namespace bcassim
