// How a load's total force is shared over its nodes when the share is estimated (issue 14: a
// tool presses somewhere in a zone, on a footprint of unknown size): log-shares quadratic in the
// zone's two in-plane coordinates, so that zero coefficients give the load's own split.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/Types.h"

namespace bcassim {

// share_k ∝ base_k exp(a u_k + b v_k - c (u_k^2 + v_k^2) / 2), normalised to sum 1, where (u, v)
// are node k's rest coordinates along the zone's two principal axes (of the base-weighted rest
// positions), from its base-weighted centroid, in units of the zone's RMS radius in that plane.
// a, b (tilts) move the centre of the force towards +u, +v; c (concentration) gathers it around
// (a, b) / c when c > 0. Dimensionless: the same prior suits a zone of any size.
class LoadFootprint {
 public:
  // `rest`: positions of `nodes` (one row each, m); `base`: their shares without a footprint
  // (empty: even). Throws InputError when the zone has fewer than 3 nodes or no extent.
  LoadFootprint(const Eigen::MatrixX3d& rest, std::vector<double> base);

  // Coefficient 0 = tilt along u, 1 = tilt along v, 2 = concentration.
  void setCoefficient(int which, double value) { coefficients_(which) = value; }
  double coefficient(int which) const { return coefficients_(which); }
  // The shares for the current coefficients (one per node, positive, summing to 1).
  std::vector<double> shares() const;
  // Rest positions' in-plane coordinates (u, v), one row per node, and the centre and RMS radius
  // they were measured from (m).
  const Eigen::MatrixX2d& coordinates() const { return uv_; }
  const Vec3& centre() const { return centre_; }
  double radius() const { return radius_; }

 private:
  std::vector<double> base_;
  Eigen::MatrixX2d uv_;
  Vec3 centre_ = Vec3::Zero();
  double radius_ = 0.0;
  Vec3 coefficients_ = Vec3::Zero();
};

}  // namespace bcassim
