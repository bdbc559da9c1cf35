#include "bcassim/mechanics/Loads.h"

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

Vec3 NodalLoad::perNodeAt(double t) const {
  const double scale = profile.value(t);
  if (frames.empty()) return scale * forcePerNode;
  const double s = t / frameDt;  // frame k sits at s = k + 1
  if (s <= 0) return Vec3::Zero();
  if (s <= 1) return scale * s * frames.front();
  const auto last = static_cast<double>(frames.size());
  if (s >= last) return scale * frames.back();
  const auto k = static_cast<size_t>(std::floor(s));  // between frames k - 1 and k
  const double w = s - static_cast<double>(k);
  return scale * ((1 - w) * frames[k - 1] + w * frames[k]);
}

Vec3 NodalLoad::totalForce() const {
  return weights.empty() ? forcePerNode * static_cast<double>(nodes.size()) : forcePerNode;
}

void NodalLoad::setTotalForce(int c, double newtons) {
  forcePerNode(c) = weights.empty() ? newtons / static_cast<double>(nodes.size()) : newtons;
}

ControlPointSet::ControlPointSet(std::vector<MappedPoint> points, Eigen::MatrixX3d restPositions,
                                 std::vector<double> times, Eigen::MatrixX3d displacements,
                                 double stiffness)
    : points_(std::move(points)),
      rest_(std::move(restPositions)),
      times_(std::move(times)),
      displacements_(std::move(displacements)),
      stiffness_(stiffness) {
  if (times_.empty() || static_cast<Eigen::Index>(times_.size()) != displacements_.rows())
    throw InputError("control points: trajectory needs at least one (time, displacement) row");
  if (!std::is_sorted(times_.begin(), times_.end()))
    throw InputError("control points: trajectory times must be increasing");
}

Vec3 ControlPointSet::displacementAt(double t) const {
  if (t <= times_.front()) return displacements_.row(0);
  if (t >= times_.back()) return displacements_.row(displacements_.rows() - 1);
  const auto it = std::upper_bound(times_.begin(), times_.end(), t);
  const Eigen::Index i = it - times_.begin();
  const double w = (t - times_[i - 1]) / (times_[i] - times_[i - 1]);
  return (1 - w) * displacements_.row(i - 1).transpose() + w * displacements_.row(i).transpose();
}

double ControlPointSet::energy(const TetMesh& mesh, const Eigen::VectorXd& x, double t) const {
  const Vec3 d = displacementAt(t);
  double W = 0;
  for (size_t i = 0; i < points_.size(); ++i) {
    const Vec3 gap = interpolate(points_[i], mesh, x) - rest_.row(i).transpose() - d;
    W += 0.5 * stiffness_ * gap.squaredNorm();
  }
  return W;
}

void ControlPointSet::addInternalForces(const TetMesh& mesh, const Eigen::VectorXd& x, double t,
                                        Eigen::VectorXd& f) const {
  const Vec3 d = displacementAt(t);
  for (size_t i = 0; i < points_.size(); ++i) {
    const MappedPoint& p = points_[i];
    const Vec3 force = stiffness_ * (interpolate(p, mesh, x) - rest_.row(i).transpose() - d);
    for (int a = 0; a < 4; ++a) f.segment<3>(3 * mesh.T(p.tet, a)) += p.weights(a) * force;
  }
}

void ControlPointSet::addForcesAndStiffness(const TetMesh& mesh, const Eigen::VectorXd& x, double t,
                                            const AssemblyPattern& pattern, double scale,
                                            Eigen::VectorXd& f, SparseMatrix& K) const {
  addInternalForces(mesh, x, t, f);
  for (const MappedPoint& p : points_) {
    Mat12 block = Mat12::Zero();
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        block.block<3, 3>(3 * a, 3 * b)
            .diagonal()
            .setConstant(scale * stiffness_ * p.weights(a) * p.weights(b));
    scatterTetBlock(pattern, p.tet, block, K);
  }
}

}  // namespace bcassim
