// The tracked frames of a served run, from the server to the scene's steps: each frame's markers
// and the step its time stamp falls on; malformed frames and frames for steps already done are
// logged in one line and skipped. Ends at an interrupt, after idleTimeout without a frame, or at
// a frame past the scene's last step.
#pragma once
#include <Eigen/Core>
#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include "bcassim/scene/Scene.h"
#include "bcassim/stream/IgtlServer.h"
#include "bcassim/stream/StepClock.h"

namespace bcassim {

struct IntakeFrame {
  long step = 0;
  double stamp = 0.0;  // s, as sent
  int client = 0;
  std::chrono::steady_clock::time_point arrival;
  Eigen::MatrixX3d markers;  // the scene's markers, m; NaN rows for markers not seen
};

class FrameIntake {
 public:
  using Log = std::function<void(const std::string&)>;
  FrameIntake(const Scene& scene, IgtlServer& server, std::optional<double> timeOffset,
              double idleTimeout, const std::atomic<bool>& interrupted, Log log);

  // The next frame for a step after `done` (waits for it); nullopt when the stream ends.
  std::optional<IntakeFrame> next(long done);
  // The stamp of a step no frame fell on.
  double stampOf(long step) const { return clock_.stampOf(step); }

  long received() const { return received_; }
  long skipped() const { return skipped_; }
  // Median interval between the arrivals of consecutive frames used, s (0 with fewer than two):
  // the camera's period as the server sees it.
  double medianFramePeriod() const;

 private:
  const Scene& scene_;
  IgtlServer& server_;
  StepClock clock_;
  double idleTimeout_;
  const std::atomic<bool>& interrupted_;
  Log log_;
  long received_ = 0, skipped_ = 0;
  std::vector<std::chrono::steady_clock::time_point> arrivals_;
};

}  // namespace bcassim
