#include "bcassim/tracking/ConstantVelocityModel.h"

namespace bcassim {

ConstantVelocityModel::ConstantVelocityModel(const Vec3& position, double time,
                                             double measurementNoise, double accelerationNoise)
    : position_(position),
      time_(time),
      measurementVariance_(measurementNoise * measurementNoise),
      accelerationVariance_(accelerationNoise * accelerationNoise) {
  covariance_ << measurementVariance_, 0.0, 0.0, 0.0;
}

Vec3 ConstantVelocityModel::predict(double time) const {
  return position_ + velocity_ * (time - time_);
}

void ConstantVelocityModel::update(const Vec3& position, double time) {
  const double dt = time - time_;
  if (updates_ == 1) {
    // Two-point start: the velocity of the difference quotient and its covariance.
    velocity_ = (position - position_) / dt;
    position_ = position;
    const double r = measurementVariance_;
    covariance_ << r, r / dt, r / dt, 2.0 * r / (dt * dt);
  } else {
    // Predict: F = [1 dt; 0 1], Q = q [dt^4/4 dt^3/2; dt^3/2 dt^2] (white-noise acceleration).
    Eigen::Matrix2d F;
    F << 1.0, dt, 0.0, 1.0;
    Eigen::Matrix2d Q;
    Q << 0.25 * dt * dt * dt * dt, 0.5 * dt * dt * dt, 0.5 * dt * dt * dt, dt * dt;
    const Eigen::Matrix2d P = F * covariance_ * F.transpose() + accelerationVariance_ * Q;
    const Vec3 predicted = position_ + velocity_ * dt;
    // Update with H = [1 0]: gain K = P H^T / (H P H^T + r), the same for every axis.
    const double innovationVariance = P(0, 0) + measurementVariance_;
    const Eigen::Vector2d gain = P.col(0) / innovationVariance;
    const Vec3 innovation = position - predicted;
    position_ = predicted + gain(0) * innovation;
    velocity_ += gain(1) * innovation;
    covariance_ = P - gain * P.row(0);
  }
  time_ = time;
  ++updates_;
}

}  // namespace bcassim
