#include "bcassim/mesh/RigidTransform.h"

namespace bcassim {

Eigen::MatrixX3d RigidTransform::apply(const Eigen::MatrixX3d& P) const {
  return (P * rotation.transpose()).rowwise() + translation.transpose();
}

RigidTransform RigidTransform::inverse() const {
  RigidTransform t;
  t.rotation = rotation.transpose();
  t.translation = -(t.rotation * translation);
  return t;
}

RigidTransform compose(const RigidTransform& second, const RigidTransform& first) {
  RigidTransform t;
  t.rotation = second.rotation * first.rotation;
  t.translation = second.rotation * first.translation + second.translation;
  return t;
}

}  // namespace bcassim
