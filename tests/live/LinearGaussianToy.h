// A linear-Gaussian toy for the live engine's tests: θ = (a, b) observed as y_k = a + b t_k +
// noise, filtered by a sequential Kalman update whose exact answer is the batch posterior in closed
// form.
#pragma once
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <random>
#include <vector>

#include "bcassim/live/Frame.h"
#include "bcassim/live/ParameterSet.h"

namespace bcassim::testing {

struct LineToy {
  Eigen::Vector2d priorMean{0.0, 0.0};
  Eigen::Matrix2d priorCovariance = Eigen::Vector2d(4.0, 9.0).asDiagonal();
  double noiseVariance = 0.01;  // of y, m²
  Eigen::Vector2d truth{1.5, -0.7};
  double framePeriod = 1.0 / 30.0;  // s

  static Eigen::RowVector2d observationRow(double time) { return {1.0, time}; }

  ParameterSet prior() const { return {priorMean, priorCovariance, -1}; }

  // Frames 0..count-1 at t_k = k T with Gaussian noise from a fixed seed.
  std::vector<Frame> frames(int count) const {
    std::mt19937 random(12345);
    std::normal_distribution<double> noise(0.0, std::sqrt(noiseVariance));
    std::vector<Frame> out;
    for (int k = 0; k < count; ++k) {
      const double t = k * framePeriod;
      Eigen::VectorXd y(1);
      y(0) = observationRow(t) * truth + noise(random);
      out.push_back({k, t, y});
    }
    return out;
  }

  // The exact posterior given the frames whose indices are listed (information form: precision
  // P0⁻¹ + Σ HᵀH / R, mean from P0⁻¹ m0 + Σ Hᵀ y / R), independent of the order of the updates.
  ParameterSet posterior(const std::vector<Frame>& all, const std::vector<long>& used) const {
    Eigen::Matrix2d precision = priorCovariance.inverse();
    Eigen::Vector2d information = precision * priorMean;
    for (long k : used) {
      const Eigen::RowVector2d h = observationRow(all[k].time);
      precision += h.transpose() * h / noiseVariance;
      information += h.transpose() * all[k].observations(0) / noiseVariance;
    }
    const Eigen::LDLT<Eigen::Matrix2d> solver(precision);
    return {solver.solve(information), solver.solve(Eigen::Matrix2d::Identity()),
            used.empty() ? -1 : used.back()};
  }
};

// The filter: one Kalman update per frame it is given (the parameters are constant, so the
// forecast is the identity).
class SequentialKalman {
 public:
  explicit SequentialKalman(const LineToy& toy)
      : mean_(toy.priorMean), covariance_(toy.priorCovariance), r_(toy.noiseVariance) {}

  ParameterSet update(const Frame& frame) {
    const Eigen::RowVector2d h = LineToy::observationRow(frame.time);
    const double s = h * covariance_ * h.transpose() + r_;
    const Eigen::Vector2d gain = covariance_ * h.transpose() / s;
    mean_ += gain * (frame.observations(0) - h * mean_);
    covariance_ -= gain * h * covariance_;
    return {mean_, covariance_, -1};
  }

 private:
  Eigen::Vector2d mean_;
  Eigen::Matrix2d covariance_;
  double r_;
};

}  // namespace bcassim::testing
