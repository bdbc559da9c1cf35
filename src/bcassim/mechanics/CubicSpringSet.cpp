#include "bcassim/mechanics/CubicSpringSet.h"

#include <fmt/format.h>

#include "bcassim/Error.h"

namespace bcassim {

CubicSpringSet::CubicSpringSet(std::vector<CubicSpring> springs,
                               std::vector<CubicSpringCoefficients> groups)
    : springs_(std::move(springs)),
      groups_(std::move(groups)),
      cutTime_(groups_.size(), std::numeric_limits<double>::infinity()) {
  for (size_t s = 0; s < springs_.size(); ++s)
    if (springs_[s].group < 0 || springs_[s].group >= static_cast<int>(groups_.size()))
      throw InputError(fmt::format("springs: spring {} is in group {} but {} groups are defined", s,
                                   springs_[s].group, groups_.size()));
}

double CubicSpringSet::magnitude(const CubicSpringCoefficients& k, double dl) {
  if (dl <= 0) return 0.0;
  return ((k.kAlpha * dl + k.kBeta) * dl + k.kGamma) * dl;
}

double CubicSpringSet::magnitudeDerivative(const CubicSpringCoefficients& k, double dl) {
  if (dl <= 0) return 0.0;  // tension-only: the tangent vanishes in compression too
  return (3.0 * k.kAlpha * dl + 2.0 * k.kBeta) * dl + k.kGamma;
}

double CubicSpringSet::potential(const CubicSpringCoefficients& k, double dl) {
  if (dl <= 0) return 0.0;
  return ((k.kAlpha / 4.0 * dl + k.kBeta / 3.0) * dl + k.kGamma / 2.0) * dl * dl;
}

CubicSpringCoefficients CubicSpringSet::activeCoefficients(int group, double t) const {
  return t >= cutTime_[group] ? CubicSpringCoefficients{} : groups_[group];
}

Vec3 CubicSpringSet::attachment(const TetMesh& mesh, const Eigen::VectorXd& x, size_t s) const {
  const CubicSpring& sp = springs_[s];
  Vec3 p = Vec3::Zero();
  for (int a = 0; a < 4; ++a) p += sp.weights(a) * x.segment<3>(3 * mesh.T(sp.tet, a));
  return p;
}

double CubicSpringSet::energy(const TetMesh& mesh, const Eigen::VectorXd& x, double t) const {
  double W = 0.0;
  for (size_t s = 0; s < springs_.size(); ++s) {
    const double L = (attachment(mesh, x, s) - springs_[s].anchor).norm();
    W += potential(activeCoefficients(springs_[s].group, t), L - springs_[s].restLength);
  }
  return W;
}

void CubicSpringSet::addInternalForces(const TetMesh& mesh, const Eigen::VectorXd& x, double t,
                                       Eigen::VectorXd& f) const {
  for (size_t s = 0; s < springs_.size(); ++s) {
    const CubicSpring& sp = springs_[s];
    const Vec3 d = attachment(mesh, x, s) - sp.anchor;
    const double L = d.norm();
    const double g = magnitude(activeCoefficients(sp.group, t), L - sp.restLength);
    if (g == 0.0) continue;
    const Vec3 force = g / L * d;
    for (int a = 0; a < 4; ++a) f.segment<3>(3 * mesh.T(sp.tet, a)) += sp.weights(a) * force;
  }
}

void CubicSpringSet::addForcesAndStiffness(const TetMesh& mesh, const Eigen::VectorXd& x, double t,
                                           const AssemblyPattern& pattern, double scale,
                                           Eigen::VectorXd& f, SparseMatrix& K) const {
  for (size_t s = 0; s < springs_.size(); ++s) {
    const CubicSpring& sp = springs_[s];
    const CubicSpringCoefficients k = activeCoefficients(sp.group, t);
    const Vec3 d = attachment(mesh, x, s) - sp.anchor;
    const double L = d.norm();
    const double dl = L - sp.restLength;
    if (dl <= 0.0) continue;
    const Vec3 n = d / L;
    const double g = magnitude(k, dl);
    for (int a = 0; a < 4; ++a) f.segment<3>(3 * mesh.T(sp.tet, a)) += sp.weights(a) * g * n;
    const Mat3 H = attachmentStiffness(mesh, x, t, s);
    Mat12 block;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        block.block<3, 3>(3 * a, 3 * b) = (scale * sp.weights(a) * sp.weights(b)) * H;
    scatterTetBlock(pattern, sp.tet, block, K);
  }
}

Mat3 CubicSpringSet::attachmentStiffness(const TetMesh& mesh, const Eigen::VectorXd& x, double t,
                                         size_t s) const {
  const CubicSpring& sp = springs_[s];
  const CubicSpringCoefficients k = activeCoefficients(sp.group, t);
  const Vec3 d = attachment(mesh, x, s) - sp.anchor;
  const double L = d.norm();
  const double dl = L - sp.restLength;
  if (dl <= 0.0) return Mat3::Zero();
  const Vec3 n = d / L;
  // d(g n)/dX = g' n n^T + g/L (I - n n^T)
  return magnitudeDerivative(k, dl) * n * n.transpose() +
         magnitude(k, dl) / L * (Mat3::Identity() - n * n.transpose());
}

}  // namespace bcassim
