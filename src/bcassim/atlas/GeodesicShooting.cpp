#include "bcassim/atlas/GeodesicShooting.h"

#include <fmt/format.h>

#include "bcassim/Error.h"

namespace bcassim {
namespace {
// s + h * v, componentwise.
ShootingState axpy(const ShootingState& s, double h, const ShootingState& v) {
  return {s.q + h * v.q, s.a + h * v.a, s.x + h * v.x};
}
void addScaled(ShootingState* s, double h, const ShootingState& v) {
  s->q += h * v.q;
  s->a += h * v.a;
  s->x += h * v.x;
}
}  // namespace

GeodesicShooting::GeodesicShooting(double sigmaV, ShootingOptions options)
    : kernel_(sigmaV), options_(options) {
  if (options_.timePoints < 2) {
    throw InputError(
        fmt::format("shooting needs at least 2 time points, got {}", options_.timePoints));
  }
}

ShootingState GeodesicShooting::velocity(const ShootingState& s) const {
  ShootingState v;
  v.q = kernel_.convolve(s.q, s.q, s.a);
  v.a = -kernel_.hamiltonianGradient(s.q, s.a);
  v.x = kernel_.convolve(s.x, s.q, s.a);
  return v;
}

ShootingState GeodesicShooting::velocityVjp(const ShootingState& s, const ShootingState& c) const {
  ShootingState g{Eigen::MatrixX3d::Zero(s.q.rows(), 3), Eigen::MatrixX3d::Zero(s.a.rows(), 3),
                  Eigen::MatrixX3d::Zero(s.x.rows(), 3)};
  // q' = K(q,q) a: q appears on both sides of the kernel.
  kernel_.convolveVjp(s.q, s.q, s.a, c.q, &g.q, &g.q, &g.a);
  // a' = -dH/dq.
  Eigen::MatrixX3d gq = Eigen::MatrixX3d::Zero(s.q.rows(), 3);
  Eigen::MatrixX3d ga = Eigen::MatrixX3d::Zero(s.q.rows(), 3);
  kernel_.hamiltonianGradientVjp(s.q, s.a, c.a, &gq, &ga);
  g.q -= gq;
  g.a -= ga;
  // x' = K(x,q) a.
  if (s.x.rows() > 0) kernel_.convolveVjp(s.x, s.q, s.a, c.x, &g.x, &g.q, &g.a);
  return g;
}

std::vector<ShootingState> GeodesicShooting::shoot(const Eigen::MatrixX3d& q0,
                                                   const Eigen::MatrixX3d& a0,
                                                   const Eigen::MatrixX3d& x0) const {
  if (q0.rows() != a0.rows()) {
    throw InputError(
        fmt::format("shooting: {} control points but {} momenta", q0.rows(), a0.rows()));
  }
  const int steps = options_.timePoints - 1;
  const double h = 1.0 / steps;
  std::vector<ShootingState> traj;
  traj.reserve(options_.timePoints);
  traj.push_back({q0, a0, x0});
  for (int k = 0; k < steps; ++k) {
    const ShootingState& s = traj.back();
    if (options_.integrator == ShootingIntegrator::Euler) {
      traj.push_back(axpy(s, h, velocity(s)));
    } else {
      const ShootingState mid = axpy(s, 0.5 * h, velocity(s));
      traj.push_back(axpy(s, h, velocity(mid)));
    }
  }
  return traj;
}

Eigen::MatrixX3d GeodesicShooting::flow(const Eigen::MatrixX3d& q0, const Eigen::MatrixX3d& a0,
                                        const Eigen::MatrixX3d& x0) const {
  return shoot(q0, a0, x0).back().x;
}

ShootingState GeodesicShooting::pullBack(const std::vector<ShootingState>& traj,
                                         const ShootingState& cotangentAtEnd) const {
  if (static_cast<int>(traj.size()) != options_.timePoints) {
    throw InputError(fmt::format("pullBack: trajectory has {} states, expected {}", traj.size(),
                                 options_.timePoints));
  }
  const int steps = options_.timePoints - 1;
  const double h = 1.0 / steps;
  ShootingState lambda = cotangentAtEnd;
  // Empty cotangent parts mean "L does not depend on it".
  const ShootingState& s0 = traj.front();
  if (lambda.q.rows() == 0) lambda.q = Eigen::MatrixX3d::Zero(s0.q.rows(), 3);
  if (lambda.a.rows() == 0) lambda.a = Eigen::MatrixX3d::Zero(s0.a.rows(), 3);
  if (lambda.x.rows() == 0) lambda.x = Eigen::MatrixX3d::Zero(s0.x.rows(), 3);
  for (int k = steps - 1; k >= 0; --k) {
    const ShootingState& s = traj[k];
    if (options_.integrator == ShootingIntegrator::Euler) {
      // s' = s + h v(s)  =>  lambda_k = lambda_{k+1} + h J(s)^T lambda_{k+1}.
      addScaled(&lambda, h, velocityVjp(s, lambda));
    } else {
      // s' = s + h v(m), m = s + h/2 v(s): recompute m rather than store it.
      const ShootingState mid = axpy(s, 0.5 * h, velocity(s));
      ShootingState mu = velocityVjp(mid, lambda);
      mu.q *= h;
      mu.a *= h;
      mu.x *= h;
      addScaled(&lambda, 1.0, mu);
      addScaled(&lambda, 0.5 * h, velocityVjp(s, mu));
    }
  }
  return lambda;
}

}  // namespace bcassim
