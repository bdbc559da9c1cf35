// Best rigid (Kabsch) or similarity (Umeyama) transform between paired point sets, optionally
// weighted: the closed-form least-squares fits used by registration with correspondences.
#pragma once
#include <Eigen/Core>

#include "bcassim/mesh/RigidTransform.h"

namespace bcassim {

// x -> s R x + t: a rigid motion with a uniform scale s > 0.
struct SimilarityTransform {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // m
  // Rows of P (#P by 3) mapped: s R p + t.
  Eigen::MatrixX3d apply(const Eigen::MatrixX3d& P) const;
};

// Rotation (det +1) and translation minimising sum_i w_i |R p_i + t - q_i|^2 (Kabsch). P, Q: #P
// by 3 paired rows, #P >= 3; weights: #P non-negative finite numbers with a positive sum, or
// empty for equal weights. Throws InputError naming what is wrong with the inputs.
RigidTransform kabschFit(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q,
                         const Eigen::VectorXd& weights = {});

// Scale, rotation (det +1) and translation minimising sum_i w_i |s R p_i + t - q_i|^2 (Umeyama
// 1991, eq. 40-42). Same inputs and errors as kabschFit; also throws InputError when the weighted
// points P all coincide (no scale can be fitted).
SimilarityTransform umeyamaFit(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q,
                               const Eigen::VectorXd& weights = {});

}  // namespace bcassim
