// What the live engine records for every frame on the real-time side: which parameters it used
// (so the filter's lag), how long it took to publish, and how many frames the filter skipped.
#pragma once

namespace bcassim {

struct FrameRecord {
  long frame = 0;
  // Frame the parameters used were analysed on (ParameterSet::frame); -1 for the prior.
  long parametersFrame = -1;
  // Frames the parameters are behind the freshest possible ones (those of frame - 1):
  // frame - 1 - parametersFrame. Always 0 in the synchronous mode.
  long lagFrames = 0;
  // Wall time of the real-time step (read the parameters, predict, hand the result to the sink),
  // s.
  double publishSeconds = 0.0;
  // Frames the filter skipped on purpose so far, including those dropped when this frame came.
  long skippedFrames = 0;
};

}  // namespace bcassim
