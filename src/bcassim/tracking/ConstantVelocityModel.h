// Position and velocity of one tracked marker from its detections: a constant-velocity Kalman
// filter (white-noise acceleration), the same on the three axes, started from two detections.
#pragma once
#include <Eigen/Core>

#include "bcassim/Types.h"

namespace bcassim {

class ConstantVelocityModel {
 public:
  // First detection at `position` (m), time `time` (s). measurementNoise: standard deviation of a
  // detection's coordinates (m); accelerationNoise: of the white-noise acceleration (m/s^2).
  ConstantVelocityModel(const Vec3& position, double time, double measurementNoise,
                        double accelerationNoise);

  // Position predicted at `time` (s, not before the last update): the last estimate moved on at
  // the estimated velocity (zero velocity after a single detection).
  Vec3 predict(double time) const;

  // Takes the detection `position` (m) at `time` (s, after the last update). The second
  // detection sets the velocity to the difference quotient; later ones are Kalman updates.
  void update(const Vec3& position, double time);

  const Vec3& velocity() const { return velocity_; }  // m/s

 private:
  Vec3 position_, velocity_ = Vec3::Zero();
  Eigen::Matrix2d covariance_;  // of (position, velocity) along each axis, m^2, m^2/s, m^2/s^2
  double time_;                 // s, of the last update
  double measurementVariance_, accelerationVariance_;
  int updates_ = 1;
};

}  // namespace bcassim
