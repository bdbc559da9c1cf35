// Small forecast models with known answers for the filter tests: a linear-Gaussian state-space
// model with its exact Kalman filter, a damped oscillator with unknown stiffness, and a static
// spring estimated from its displacement alone (parameter-only state).
#pragma once
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/QR>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "bcassim/assimilation/ForecastModel.h"
#include "bcassim/assimilation/Observation.h"
#include "bcassim/assimilation/StochasticState.h"

namespace bcassim::testing {

// x_{i+1} = A x_i + B theta + f sin(0.3 i), z = H x_{i+1}; theta enters linearly and is constant.
struct LinearSystem {
  Eigen::MatrixXd A, B, H;
  Eigen::VectorXd f;
  Eigen::VectorXd forcing(int step) const { return f * std::sin(0.3 * step); }

  static LinearSystem make() {
    LinearSystem s;
    s.A.resize(3, 3);
    s.A << 0.95, 0.10, 0.00, -0.10, 0.90, 0.05, 0.02, 0.00, 0.97;
    s.B.resize(3, 2);
    s.B << 0.10, 0.00, 0.05, 0.20, 0.00, 0.10;
    s.H.resize(4, 3);
    s.H << 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5, 0.5, 0;
    s.f = Eigen::Vector3d(0.2, -0.1, 0.05);
    return s;
  }
};

class LinearModel final : public ForecastModel {
 public:
  explicit LinearModel(const LinearSystem& s) : s_(s) {}
  Eigen::Index stateSize() const override { return s_.A.rows(); }
  Eigen::Index observableSize() const override { return s_.H.rows(); }
  void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                Eigen::VectorXd& newState, Eigen::VectorXd& predicted) override {
    newState = s_.A * state + s_.B * params + s_.forcing(step_);
    predicted = s_.H * newState;
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd&) override { ++step_; }

 private:
  const LinearSystem& s_;
  int step_ = 0;
};

// The exact Kalman filter on the augmented state [x; theta] with F = [A B; 0 I].
class ExactKalman {
 public:
  ExactKalman(const LinearSystem& s, Eigen::VectorXd mean, Eigen::MatrixXd cov,
              Eigen::VectorXd processVariance = {})
      : s_(s), x_(std::move(mean)), P_(std::move(cov)), q_(std::move(processVariance)) {
    const Eigen::Index m = s.A.rows(), p = s.B.cols();
    F_.setZero(m + p, m + p);
    F_.topLeftCorner(m, m) = s.A;
    F_.topRightCorner(m, p) = s.B;
    F_.bottomRightCorner(p, p).setIdentity();
    Hf_.setZero(s.H.rows(), m + p);
    Hf_.leftCols(m) = s.H;
  }
  void step(const Observation& y) {
    const Eigen::Index m = s_.A.rows();
    x_ = F_ * x_;
    x_.head(m) += s_.forcing(step_++);
    P_ = F_ * P_ * F_.transpose();
    if (q_.size()) P_.diagonal() += q_;
    if (y.values.size() == 0) return;
    std::vector<Eigen::Index> rows;
    for (Eigen::Index i = 0; i < y.values.size(); ++i)
      if (y.present.empty() || y.present[i]) rows.push_back(i);
    const auto k = static_cast<Eigen::Index>(rows.size());
    Eigen::MatrixXd H(k, x_.size()), R = Eigen::MatrixXd::Zero(k, k);
    Eigen::VectorXd z(k);
    for (Eigen::Index a = 0; a < k; ++a) {
      H.row(a) = Hf_.row(rows[a]);
      z[a] = y.values[rows[a]];
      R(a, a) = y.variance[rows[a]];
    }
    const Eigen::MatrixXd S = H * P_ * H.transpose() + R;
    const Eigen::MatrixXd K = P_ * H.transpose() * S.inverse();
    x_ += K * (z - H * x_);
    P_ = P_ - K * S * K.transpose();
  }
  const Eigen::VectorXd& mean() const { return x_; }
  const Eigen::MatrixXd& covariance() const { return P_; }

 private:
  const LinearSystem& s_;
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  Eigen::VectorXd q_;
  Eigen::MatrixXd F_, Hf_;
  int step_ = 0;
};

// The linear system's runs: steps and true parameters.
inline constexpr int kLinearSteps = 8;
inline const Eigen::Vector2d kLinearTheta(1.0, -0.5);

// The linear system's prior: state (0.2, -0.1, 0) with `physicalSigma` on each entry, parameters
// a = 0.5 ± 0.4 and b = 0 ± 0.3; and the exact Kalman filter started from it.
inline StochasticState linearLayout(double physicalSigma) {
  return StochasticState(Eigen::Vector3d(0.2, -0.1, 0.0), Eigen::Vector3d::Constant(physicalSigma),
                         {{"a", 0.5, 0.4, {}}, {"b", 0.0, 0.3, {}}});
}

inline ExactKalman exactFor(const LinearSystem& s, const StochasticState& layout,
                            Eigen::VectorXd q = {}) {
  return ExactKalman(s, layout.initialMean(),
                     layout.initialStddev().array().square().matrix().asDiagonal(), std::move(q));
}

// Observation frames of a true run: noise sigma; frame 3 misses entries 1 and 3 (NaN there), frame
// 5 is empty, the others are complete.
inline std::vector<Observation> linearFrames(const LinearSystem& s, const Eigen::VectorXd& theta,
                                             int steps, double sigma, unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  Eigen::VectorXd x = Eigen::Vector3d(0.3, -0.2, 0.1);
  std::vector<Observation> frames;
  for (int i = 0; i < steps; ++i) {
    x = s.A * x + s.B * theta + s.forcing(i);
    Eigen::VectorXd z = s.H * x;
    for (Eigen::Index k = 0; k < z.size(); ++k) z[k] += noise(rng);
    Observation y = Observation::withSigma(z, sigma);
    if (i == 3) {
      y.present = {true, false, true, false};
      y.values[1] = y.values[3] = std::nan("");
    }
    if (i == 5) y = Observation::none();
    frames.push_back(y);
  }
  return frames;
}

// Damped, forced oscillator x'' = -k x - c x' + sin(w t), symplectic Euler; state [x, v], one
// parameter k, observes x.
class Oscillator final : public ForecastModel {
 public:
  static constexpr double dt = 0.05, damping = 0.2, omega = 1.3;
  Eigen::Index stateSize() const override { return 2; }
  Eigen::Index observableSize() const override { return 1; }
  void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                Eigen::VectorXd& newState, Eigen::VectorXd& predicted) override {
    newState = advance(state, params[0], step_);
    predicted = newState.head(1);
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd&) override { ++step_; }
  static Eigen::VectorXd advance(const Eigen::VectorXd& s, double k, int step) {
    Eigen::VectorXd out(2);
    out[1] = s[1] + dt * (-k * s[0] - damping * s[1] + std::sin(omega * step * dt));
    out[0] = s[0] + dt * out[1];
    return out;
  }

 private:
  int step_ = 0;
};

inline std::vector<Observation> oscillatorFrames(double k, int steps, double sigma) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, sigma);
  Eigen::VectorXd s = Eigen::Vector2d(0.1, 0.0);
  std::vector<Observation> frames;
  for (int i = 0; i < steps; ++i) {
    s = Oscillator::advance(s, k, i);
    frames.push_back(
        Observation::withSigma(Eigen::VectorXd::Constant(1, s[0] + noise(rng)), sigma));
  }
  return frames;
}

// A spring under the load 1 + 0.5 sin(0.2 i): displacement load/k, no physical state at all.
class StaticSpring final : public ForecastModel {
 public:
  static double load(int step) { return 1.0 + 0.5 * std::sin(0.2 * step); }
  Eigen::Index stateSize() const override { return 0; }
  Eigen::Index observableSize() const override { return 1; }
  void forecast(const Eigen::VectorXd&, const Eigen::VectorXd& params, Eigen::VectorXd& newState,
                Eigen::VectorXd& predicted) override {
    newState.resize(0);
    predicted = Eigen::VectorXd::Constant(1, load(step_ + 1) / params[0]);
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd&) override { ++step_; }

 private:
  int step_ = 0;
};

// y = h(o) = (o0^2, o0 o1, o1^2) and its Jacobian: a nonlinear observation whose maximum a
// posteriori estimate a few Gauss-Newton steps find.
struct Quadratic {
  static Eigen::Vector3d h(const Eigen::Vector2d& o) {
    return {o(0) * o(0), o(0) * o(1), o(1) * o(1)};
  }
  static Eigen::Matrix<double, 3, 2> jacobian(const Eigen::Vector2d& o) {
    Eigen::Matrix<double, 3, 2> J;
    J << 2 * o(0), 0, o(1), o(0), 0, 2 * o(1);
    return J;
  }
};

// A random symmetric positive definite n x n matrix with eigenvalues in [0.1, 2.1].
inline Eigen::MatrixXd randomSpd(Eigen::Index n, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.1, 2.1);
  Eigen::MatrixXd M(n, n);
  for (Eigen::Index i = 0; i < M.size(); ++i) M.data()[i] = g(rng);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(M);
  const Eigen::MatrixXd Q = qr.householderQ();
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) d[i] = u(rng);
  return Q * d.asDiagonal() * Q.transpose();
}

}  // namespace bcassim::testing
