// Wall-clock timing of steps and runs, in seconds, on the steady (monotonic) clock.
#pragma once
#include <chrono>

namespace bcassim {

using Clock = std::chrono::steady_clock;

// Seconds from a to b.
inline double secondsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// Seconds elapsed since t0.
inline double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace bcassim
