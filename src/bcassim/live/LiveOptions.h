// Options of the live engine: synchronous or asynchronous, and how far the filter may fall behind
// before it skips frames.
#pragma once

namespace bcassim {

enum class LiveMode {
  // No thread: every frame is predicted, then analysed, on the caller's thread (lag 0). The
  // reference to compare the asynchronous mode with.
  Synchronous,
  // The filter runs on its own thread behind the real-time side (thesis §4.6, §5.4).
  Asynchronous,
};

struct LiveOptions {
  LiveMode mode = LiveMode::Asynchronous;
  // Frames that may wait for the filter (>= 1). Beyond it, the oldest waiting frames are skipped:
  // at a frame period T (s), the filter's analysis is at most about (maxLagFrames + 1) T old.
  int maxLagFrames = 8;
};

}  // namespace bcassim
