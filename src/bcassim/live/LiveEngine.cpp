// The real-time side, the filter thread and their start and stop (LiveEngine.h).
#include "bcassim/live/LiveEngine.h"

#include <fmt/format.h>

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"

namespace bcassim {

LiveEngine::LiveEngine(ParameterSet prior, RealTimeStep realTime, FilterStep filter,
                       LiveOptions options)
    : options_(options),
      realTime_(std::move(realTime)),
      filter_(std::move(filter)),
      exchange_(std::move(prior)),
      mailbox_(options.maxLagFrames) {
  if (!realTime_ || !filter_)
    throw InputError("LiveEngine: a real-time step and a filter step are both required");
  if (options_.mode == LiveMode::Asynchronous) thread_ = std::thread([this] { filterLoop(); });
}

LiveEngine::~LiveEngine() {
  if (thread_.joinable()) {
    mailbox_.close(true);
    thread_.join();
  }
}

void LiveEngine::push(Frame frame) {
  if (finished_) throw std::logic_error("LiveEngine::push after finish()");
  if (frame.index != nextIndex_)
    throw InputError("live frame: index " + std::to_string(frame.index) + ", expected " +
                     std::to_string(nextIndex_) +
                     " (frames are numbered 0, 1, 2, ... as they come)");
  if (nextIndex_ > 0 && !(frame.time > lastTime_))
    throw InputError(
        fmt::format("live frame {}: time {} s, expected after the previous frame's {} s",
                    frame.index, frame.time, lastTime_));
  ++nextIndex_;
  lastTime_ = frame.time;

  const Clock::time_point start = Clock::now();
  const std::shared_ptr<const ParameterSet> parameters = exchange_.latest();
  realTime_(frame, *parameters);
  const double publishSeconds = secondsSince(start);

  FrameRecord record;
  record.frame = frame.index;
  record.parametersFrame = parameters->frame;
  record.lagFrames = frame.index - 1 - parameters->frame;
  record.publishSeconds = publishSeconds;
  record.skippedFrames = mailbox_.put(std::move(frame));
  records_.push_back(record);

  if (options_.mode == LiveMode::Synchronous && !failure_) {
    try {
      analyseNext();
    } catch (...) {
      // Kept for finish(), as in the asynchronous mode, so that both modes end the same way.
      failure_ = std::current_exception();
      mailbox_.close(true);
    }
  }
}

bool LiveEngine::analyseNext() {
  std::optional<Frame> frame = mailbox_.take();
  if (!frame) return false;
  ParameterSet next = filter_(*frame);
  next.frame = frame->index;
  exchange_.publish(std::make_shared<const ParameterSet>(std::move(next)));
  analysed_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

void LiveEngine::filterLoop() {
  try {
    while (analyseNext()) {
    }
  } catch (...) {
    // Never lost and never std::terminate: finish() rethrows it on the caller's thread. Frames
    // that come later are counted as skipped.
    failure_ = std::current_exception();
    mailbox_.close(true);
  }
}

LiveSummary LiveEngine::finish(FinishMode mode) {
  if (finished_) throw std::logic_error("LiveEngine::finish called twice");
  finished_ = true;
  mailbox_.close(mode == FinishMode::DropWaiting);
  if (thread_.joinable()) thread_.join();  // none in the synchronous mode
  if (failure_) std::rethrow_exception(failure_);
  LiveSummary summary;
  summary.frames = nextIndex_;
  summary.analysed = analysed_.load(std::memory_order_relaxed);
  summary.skipped = mailbox_.skipped();
  return summary;
}

}  // namespace bcassim
