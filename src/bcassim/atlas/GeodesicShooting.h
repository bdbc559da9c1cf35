// Geodesic shooting of LDDMM, thesis eq. 4.4: q' = K(q,q) a, a' = -d/dq (1/2 a^T K(q,q) a), on
// t in [0, 1], dragging any point set along x' = K(x,q) a; with its exact discrete adjoint.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/atlas/GaussianKernel.h"

namespace bcassim {

enum class ShootingIntegrator {
  Euler,  // forward Euler: first order
  Rk2,    // explicit midpoint: second order
};

struct ShootingOptions {
  int timePoints = 11;  // including t = 0 and t = 1, so timePoints - 1 steps; >= 2
  ShootingIntegrator integrator = ShootingIntegrator::Euler;
};

// Control points, momenta and dragged points at one time point.
struct ShootingState {
  Eigen::MatrixX3d q;  // #q by 3 control points (m)
  Eigen::MatrixX3d a;  // #q by 3 momenta (m per unit time, before the kernel)
  Eigen::MatrixX3d x;  // #x by 3 flowed points (m); may have no rows
};

class GeodesicShooting {
 public:
  // sigmaV: deformation kernel width (m). Throws InputError on bad options.
  explicit GeodesicShooting(double sigmaV, ShootingOptions options = {});

  const GaussianKernel& kernel() const { return kernel_; }
  const ShootingOptions& options() const { return options_; }

  // States at the options().timePoints time points; front() is the input, back() is t = 1.
  // q0, a0: #q by 3; x0: #x by 3.
  std::vector<ShootingState> shoot(const Eigen::MatrixX3d& q0, const Eigen::MatrixX3d& a0,
                                   const Eigen::MatrixX3d& x0) const;

  // Positions at t = 1 of the points x0 (#x by 3) flowed by the geodesic from (q0, a0).
  Eigen::MatrixX3d flow(const Eigen::MatrixX3d& q0, const Eigen::MatrixX3d& a0,
                        const Eigen::MatrixX3d& x0) const;

  // Reverse sweep through the discrete scheme of shoot(): given dL/d(state at t = 1) returns
  // dL/d(state at t = 0) exactly (to rounding) for the trajectory returned by shoot().
  ShootingState pullBack(const std::vector<ShootingState>& trajectory,
                         const ShootingState& cotangentAtEnd) const;

 private:
  ShootingState velocity(const ShootingState& s) const;
  ShootingState velocityVjp(const ShootingState& s, const ShootingState& cotangent) const;

  GaussianKernel kernel_;
  ShootingOptions options_;
};

}  // namespace bcassim
