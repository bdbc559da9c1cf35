#include "bcassim/calibration/SpringLattice.h"

#include <fmt/format.h>

#include "bcassim/Error.h"

namespace bcassim {

SpringLattice::SpringLattice(const Vec3& size, int nx, int ny, int nz)
    : size_(size), nx_(nx), ny_(ny), nz_(nz) {
  if ((size.array() <= 0).any() || !size.allFinite())
    throw InputError(fmt::format("spring lattice: sizes must be > 0 m, got {} x {} x {}", size(0),
                                 size(1), size(2)));
  if (nx < 1 || ny < 1 || nz < 1)
    throw InputError(
        fmt::format("spring lattice: cell counts must be >= 1, got {} x {} x {}", nx, ny, nz));
  const int n = (nx + 1) * (ny + 1) * (nz + 1);
  rest_.resize(3 * n);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        rest_.segment<3>(3 * node(i, j, k)) =
            Vec3(size(0) * i / nx, size(1) * j / ny, size(2) * k / nz);
  const auto add = [&](int a, int b, bool diagonal) {
    springs_.push_back(
        {a, b, (rest_.segment<3>(3 * b) - rest_.segment<3>(3 * a)).norm(), diagonal});
  };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const int p = node(i, j, k);
        if (i < nx) add(p, node(i + 1, j, k), false);
        if (j < ny) add(p, node(i, j + 1, k), false);
        if (k < nz) add(p, node(i, j, k + 1), false);
        if (i < nx && j < ny) {  // xy face
          add(p, node(i + 1, j + 1, k), true);
          add(node(i + 1, j, k), node(i, j + 1, k), true);
        }
        if (i < nx && k < nz) {  // xz face
          add(p, node(i + 1, j, k + 1), true);
          add(node(i + 1, j, k), node(i, j, k + 1), true);
        }
        if (j < ny && k < nz) {  // yz face
          add(p, node(i, j + 1, k + 1), true);
          add(node(i, j + 1, k), node(i, j, k + 1), true);
        }
      }
}

double SpringLattice::energy(const Eigen::VectorXd& x, const CubicSpringCoefficients& k) const {
  double W = 0.0;
  for (const LatticeSpring& s : springs_) {
    const double L = (x.segment<3>(3 * s.b) - x.segment<3>(3 * s.a)).norm();
    W += CubicSpringSet::potential(k, L - s.restLength);
  }
  return W;
}

bool SpringLattice::springForce(const Eigen::VectorXd& x, const CubicSpringCoefficients& k,
                                size_t s, Vec3& force, Mat3* H) const {
  const LatticeSpring& sp = springs_[s];
  const Vec3 d = x.segment<3>(3 * sp.b) - x.segment<3>(3 * sp.a);
  const double L = d.norm();
  const double dl = L - sp.restLength;
  if (dl <= 0.0) return false;  // tension-only (eq. 2.26)
  const Vec3 n = d / L;
  const double g = CubicSpringSet::magnitude(k, dl);
  // W = potential(|x_b - x_a| - L0): dW/dx_b = g n, dW/dx_a = -g n.
  force = g * n;
  if (H) {
    const Mat3 nn = n * n.transpose();
    *H = CubicSpringSet::magnitudeDerivative(k, dl) * nn + g / L * (Mat3::Identity() - nn);
  }
  return true;
}

void SpringLattice::forces(const Eigen::VectorXd& x, const CubicSpringCoefficients& k,
                           Eigen::VectorXd& f, std::vector<Eigen::Triplet<double>>* K) const {
  f.setZero(x.size());
  if (K) K->clear();
  Vec3 force;
  Mat3 H;
  for (size_t s = 0; s < springs_.size(); ++s) {
    if (!springForce(x, k, s, force, K ? &H : nullptr)) continue;
    const int a = springs_[s].a, b = springs_[s].b;
    f.segment<3>(3 * b) += force;
    f.segment<3>(3 * a) -= force;
    if (!K) continue;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        const double h = H(r, c);
        K->emplace_back(3 * a + r, 3 * a + c, h);
        K->emplace_back(3 * b + r, 3 * b + c, h);
        K->emplace_back(3 * a + r, 3 * b + c, -h);
        K->emplace_back(3 * b + r, 3 * a + c, -h);
      }
  }
}

}  // namespace bcassim
