// The asynchronous assimilation engine (thesis §4.6, §5.4): every frame is predicted and
// published at once with the latest analysed parameters, while the filter runs behind on its own
// thread and skips frames on purpose when it falls too far behind. Also a synchronous mode.
#pragma once
#include <atomic>
#include <exception>
#include <memory>
#include <thread>
#include <vector>

#include "bcassim/live/FrameMailbox.h"
#include "bcassim/live/FrameRecord.h"
#include "bcassim/live/LiveOptions.h"
#include "bcassim/live/LiveSteps.h"
#include "bcassim/live/ParameterExchange.h"

namespace bcassim {

enum class FinishMode {
  // The filter analyses every frame still waiting before finish() returns.
  Drain,
  // The waiting frames are skipped (and counted); the frame being analysed is finished.
  DropWaiting,
};

struct LiveSummary {
  long frames = 0;    // pushed
  long analysed = 0;  // by the filter
  long skipped = 0;   // on purpose: frames - analysed, unless a real-time step threw
};

class LiveEngine {
 public:
  // Throws InputError for a prior of the wrong shape or options.maxLagFrames < 1. In the
  // asynchronous mode the filter thread starts here and waits for frames.
  LiveEngine(ParameterSet prior, RealTimeStep realTime, FilterStep filter, LiveOptions options);
  // Without finish(): the waiting frames are dropped, the thread joined, a filter error ignored.
  ~LiveEngine();
  LiveEngine(const LiveEngine&) = delete;
  LiveEngine& operator=(const LiveEngine&) = delete;

  // The real-time side, called from one thread (the camera's) for every frame: runs the
  // real-time step with the latest parameters, records the frame, and hands it to the filter
  // without waiting for it (synchronous mode: analyses it before returning). Throws InputError
  // for a frame out of order. An exception of the real-time step goes to the caller, and that
  // frame is neither recorded, analysed nor counted as skipped; the next frame's index follows
  // it. After a filter error, frames are still predicted (with the last parameters) and counted
  // as skipped.
  void push(Frame frame);

  // Ends the run and joins the filter thread; rethrows the exception the filter threw, if any.
  LiveSummary finish(FinishMode mode = FinishMode::Drain);

  // One record per pushed frame, in order. Read it from the pushing thread or after finish().
  const std::vector<FrameRecord>& records() const { return records_; }

  // The latest published parameters (the prior before the first analysis).
  std::shared_ptr<const ParameterSet> latest() const { return exchange_.latest(); }

 private:
  // Takes and analyses one frame; false when the mailbox is closed and empty.
  bool analyseNext();
  void filterLoop();

  LiveOptions options_;
  RealTimeStep realTime_;
  FilterStep filter_;
  ParameterExchange exchange_;
  FrameMailbox mailbox_;
  std::vector<FrameRecord> records_;
  long nextIndex_ = 0;
  double lastTime_ = 0.0;
  std::atomic<long> analysed_{0};
  // Set by the filter thread before it ends; read by finish() after the join, which orders them.
  std::exception_ptr failure_;
  bool finished_ = false;
  std::thread thread_;  // last: started once everything it uses exists
};

}  // namespace bcassim
