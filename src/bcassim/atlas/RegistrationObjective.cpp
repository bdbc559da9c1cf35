#include "bcassim/atlas/RegistrationObjective.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

RegistrationObjective::RegistrationObjective(const TriMesh& source, const SurfaceDistance& distance,
                                             const GeodesicShooting& shooting,
                                             Eigen::MatrixX3d controlPoints, double dataWeight)
    : source_(source),
      distance_(distance),
      shooting_(shooting),
      q0_(std::move(controlPoints)),
      weight_(dataWeight) {
  if (!(dataWeight > 0.0) || !std::isfinite(dataWeight)) {
    throw InputError(fmt::format("registration data weight must be positive, got {}", dataWeight));
  }
  if (q0_.rows() == 0) throw InputError("registration needs at least one control point");
}

RegistrationTerms RegistrationObjective::evaluate(const Eigen::MatrixX3d& a0,
                                                  Eigen::MatrixX3d* grad) const {
  return evaluateAt(source_.V, a0, grad, nullptr);
}

RegistrationTerms RegistrationObjective::evaluateAt(const Eigen::MatrixX3d& V,
                                                    const Eigen::MatrixX3d& a0,
                                                    Eigen::MatrixX3d* gradA,
                                                    Eigen::MatrixX3d* gradV) const {
  if (a0.rows() != q0_.rows()) {
    throw InputError(
        fmt::format("registration: {} momenta for {} control points", a0.rows(), q0_.rows()));
  }
  if (V.rows() != source_.V.rows()) {
    throw InputError(
        fmt::format("registration: {} vertices for a source of {}", V.rows(), source_.V.rows()));
  }
  const std::vector<ShootingState> traj = shooting_.shoot(q0_, a0, V);
  const Eigen::MatrixX3d Ka = shooting_.kernel().convolve(q0_, q0_, a0);
  RegistrationTerms t;
  t.regularity = (a0.array() * Ka.array()).sum();
  if (!gradA && !gradV) {
    t.data = distance_.value(traj.back().x, source_.F);
  } else {
    ShootingState c;
    t.data = distance_.valueAndGradient(traj.back().x, source_.F, &c.x);
    c.x *= weight_;
    ShootingState g = shooting_.pullBack(traj, c);
    if (gradA) *gradA = g.a + 2.0 * Ka;  // d(a^T K a)/da = 2 K a
    if (gradV) *gradV = std::move(g.x);
  }
  t.total = weight_ * t.data + t.regularity;
  return t;
}

Eigen::MatrixX3d RegistrationObjective::deform(const Eigen::MatrixX3d& a0) const {
  return shooting_.flow(q0_, a0, source_.V);
}

}  // namespace bcassim
