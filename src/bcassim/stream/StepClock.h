// Which step of a scene a frame's time stamp falls on: step k is the time offset + k dt, frames
// are rounded to the nearest step. Without an offset the first frame fixes it (it is step 1),
// so a camera's wall-clock time stamps work as well as a recording's scene times.
#pragma once
#include <cmath>
#include <optional>

namespace bcassim {

class StepClock {
 public:
  // dt: the scene's time step, s (> 0). offset: the stamp of the scene's t = 0, s.
  StepClock(double dt, std::optional<double> offset) : dt_(dt), offset_(offset) {}

  long stepOf(double stamp) {
    if (!offset_) offset_ = stamp - dt_;
    return std::lround((stamp - *offset_) / dt_);
  }
  // The stamp of `step` (once the offset is known; before, the scene's time).
  double stampOf(long step) const {
    return offset_.value_or(0.0) + static_cast<double>(step) * dt_;
  }

 private:
  double dt_;
  std::optional<double> offset_;
};

}  // namespace bcassim
