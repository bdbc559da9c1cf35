#include "bcassim/calibration/LatticeStretch.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

LatticeStretch::LatticeStretch(const SpringLattice& lattice, LatticeStretchOptions options)
    : lattice_(&lattice), options_(options) {
  const int n = lattice.numNodes();
  freeIndex_.assign(3 * n, -1);
  const int nx = lattice.cells(0), ny = lattice.cells(1), nz = lattice.cells(2);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const int p = lattice.node(i, j, k);
        if (j == ny) pulled_.push_back(p);
        if (j == 0 || j == ny) continue;
        freeNodes_.push_back(p);
        for (int c = 0; c < 3; ++c) freeIndex_[3 * p + c] = numFree_++;
      }
  std::vector<Eigen::Triplet<double>> pattern;
  for (int i = 0; i < numFree_; ++i) pattern.emplace_back(i, i, 0.0);
  const auto blocks = [&](const LatticeSpring& s) {
    return std::array<std::pair<int, int>, 4>{{{s.a, s.a}, {s.b, s.b}, {s.a, s.b}, {s.b, s.a}}};
  };
  for (const LatticeSpring& s : lattice.springs())
    for (const auto& [p, q] : blocks(s))
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          const int i = freeIndex_[3 * p + r], j = freeIndex_[3 * q + c];
          if (i >= 0 && j >= 0) pattern.emplace_back(i, j, 0.0);
        }
  K_.resize(numFree_, numFree_);
  K_.setFromTriplets(pattern.begin(), pattern.end());
  K_.makeCompressed();
  const auto slot = [&](int i, int j) {
    for (int k = K_.outerIndexPtr()[j]; k < K_.outerIndexPtr()[j + 1]; ++k)
      if (K_.innerIndexPtr()[k] == i) return k;
    return -1;
  };
  for (int i = 0; i < numFree_; ++i) diagonal_.push_back(slot(i, i));
  for (const LatticeSpring& s : lattice.springs()) {
    std::array<int, 36> sl;
    int n = 0;
    for (const auto& [p, q] : blocks(s))
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          const int i = freeIndex_[3 * p + r], j = freeIndex_[3 * q + c];
          sl[n++] = i >= 0 && j >= 0 ? slot(i, j) : -1;
        }
    slots_.push_back(sl);
  }
  ldlt_.analyzePattern(K_);
}

double LatticeStretch::reaction(const CubicSpringCoefficients& k, const Eigen::VectorXd& x) const {
  Eigen::VectorXd f;
  lattice_->forces(x, k, f);
  double R = 0.0;
  for (int p : pulled_) R += f(3 * p + 1);
  return R;
}

double LatticeStretch::solve(const CubicSpringCoefficients& k, double d, Eigen::VectorXd& x) {
  const Eigen::VectorXd& rest = lattice_->restPositions();
  const double length = lattice_->size()(1);
  if (x.size() != rest.size()) x = rest;
  // Affine predictor along y from the displacement x was at.
  const double from = x(3 * pulled_.front() + 1) - rest(3 * pulled_.front() + 1);
  for (int p : freeNodes_) x(3 * p + 1) += (d - from) * rest(3 * p + 1) / length;
  for (int p = 0; p < lattice_->numNodes(); ++p)
    if (freeIndex_[3 * p] < 0) x.segment<3>(3 * p) = rest.segment<3>(3 * p);
  for (int p : pulled_) x(3 * p + 1) += d;

  Eigen::VectorXd r(numFree_), dx(numFree_), trial, values(K_.nonZeros());
  const auto& springs = lattice_->springs();
  Vec3 force;
  Mat3 H;
  for (iterations_ = 0;; ++iterations_) {
    f_.setZero(x.size());
    Eigen::Map<Eigen::VectorXd> Kv(K_.valuePtr(), K_.nonZeros());
    Kv.setZero();
    for (size_t s = 0; s < springs.size(); ++s) {
      if (!lattice_->springForce(x, k, s, force, &H)) continue;
      f_.segment<3>(3 * springs[s].b) += force;
      f_.segment<3>(3 * springs[s].a) -= force;
      const std::array<int, 36>& sl = slots_[s];
      for (int blk = 0; blk < 4; ++blk) {
        const double sign = blk < 2 ? 1.0 : -1.0;
        for (int e = 0; e < 9; ++e)
          if (sl[9 * blk + e] >= 0) Kv(sl[9 * blk + e]) += sign * H(e / 3, e % 3);
      }
    }
    double R = 0.0;
    for (int p : pulled_) R += f_(3 * p + 1);
    for (size_t i = 0; i < freeIndex_.size(); ++i)
      if (freeIndex_[i] >= 0) r(freeIndex_[i]) = f_(i);
    if (!r.allFinite())
      throw NumericalError(fmt::format("spring lattice: non-finite forces at d = {:.6g} m", d));
    if (r.norm() <= options_.relativeTolerance * std::abs(R) || r.norm() == 0.0) return R;
    if (iterations_ == options_.maxIterations)
      throw NumericalError(
          fmt::format("spring lattice: Newton did not converge in {} iterations at d = {:.6g} m "
                      "(residual {:.3g} N, reaction {:.3g} N)",
                      options_.maxIterations, d, r.norm(), R));
    double maxDiagonal = 0.0;
    for (int slot : diagonal_) maxDiagonal = std::max(maxDiagonal, Kv(slot));
    values = Kv;
    // Slack springs leave directions without stiffness (the rest state, compressed springs) and a
    // softening law can make K indefinite: shift the diagonal until the factor is positive.
    double shift = 0.0;
    for (int attempt = 0;; ++attempt) {
      Kv = values;
      for (int slot : diagonal_) Kv(slot) += shift;
      ldlt_.factorize(K_);
      if (ldlt_.info() == Eigen::Success && (ldlt_.vectorD().array() > 0).all()) break;
      if (attempt == 60)
        throw NumericalError(
            fmt::format("spring lattice: no positive definite tangent at d = {:.6g} m", d));
      shift = shift == 0.0 ? 1e-10 * std::max(maxDiagonal, 1e-12) : 10.0 * shift;
    }
    dx = -ldlt_.solve(r);
    // Backtracking on the energy (Armijo), the step accepted if the energy stalls at round-off.
    const double W0 = lattice_->energy(x, k), slope = r.dot(dx);
    double alpha = 1.0;
    for (int ls = 0; ls < 30; ++ls, alpha *= 0.5) {
      trial = x;
      for (size_t i = 0; i < freeIndex_.size(); ++i)
        if (freeIndex_[i] >= 0) trial(i) += alpha * dx(freeIndex_[i]);
      const double W = lattice_->energy(trial, k);
      if (W <= W0 + 1e-4 * alpha * slope + 1e-13 * std::abs(W0)) break;
    }
    x = trial;
  }
}

}  // namespace bcassim
