// How `bcassim serve` runs a scene for navigation software: which mode, how frames' time stamps
// map to steps, when to stop, what to send (SI units: s, m).
#pragma once
#include <optional>
#include <string>

#include "bcassim/navigation/RealTimeModel.h"

namespace bcassim {

enum class ServeMode {
  // The filter's step is in the loop: each frame is analysed, then its prediction is sent.
  Synchronous,
  // A real-time model sends each frame's prediction at once with the latest analysis; the filter
  // runs behind on its own thread and skips frames on purpose when too far behind (thesis §4.6).
  Asynchronous,
};

struct ServeOptions {
  ServeMode mode = ServeMode::Synchronous;
  std::string outDir = "out/serve";
  // Stamp of the scene's t = 0, s; none: the first frame is step 1 (a camera's clock).
  std::optional<double> timeOffset = 0.0;
  double idleTimeout = 0.0;  // s without a frame before the run ends; 0: never
  bool sendSurface = true;
  int maxLagFrames = 8;  // asynchronous: frames that may wait for the filter (>= 1)
  // Asynchronous: the filter waits this long before each frame, s. For tests and demonstrations
  // of a filter slower than the camera; 0 in use.
  double filterDelay = 0.0;
  // Asynchronous: how the real-time model steps (RealTimeModel.h). Frozen by default: with the
  // builds below the real-time step's priority, real-time step p99 8.5 ms against 46 ms on
  // LiTS-3 (docs/live.md); the filter, sharing its core with the builds, analyses fewer frames.
  RealTimeTangent realTimeTangent = RealTimeTangent::Frozen;
};

}  // namespace bcassim
