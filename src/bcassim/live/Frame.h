// One camera frame as the live engine receives it: its number, its time and the observations
// taken on it (e.g. marker coordinates, m).
#pragma once
#include <Eigen/Core>

namespace bcassim {

struct Frame {
  // 0, 1, 2, ... in arrival order (LiveEngine::push checks it).
  long index = 0;
  // Acquisition time, s; strictly increasing from frame to frame.
  double time = 0.0;
  // What was measured on this frame; its meaning is the filter's business, never the engine's.
  Eigen::VectorXd observations;
};

}  // namespace bcassim
