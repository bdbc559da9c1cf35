// The bounded, skip-oldest mailbox of FrameMailbox.h.
#include "bcassim/live/FrameMailbox.h"

#include <string>
#include <utility>

#include "bcassim/Error.h"

namespace bcassim {

namespace {
std::size_t checkedCapacity(int capacity) {
  if (capacity < 1)
    throw InputError("LiveOptions.maxLagFrames: " + std::to_string(capacity) +
                     ", expected at least 1 frame waiting for the filter");
  return static_cast<std::size_t>(capacity);
}
}  // namespace

FrameMailbox::FrameMailbox(int capacity) : capacity_(checkedCapacity(capacity)) {}

long FrameMailbox::put(Frame frame) {
  long skipped = 0;
  {
    std::lock_guard lock(mutex_);
    if (closed_) return ++skipped_;
    waiting_.push_back(std::move(frame));
    // The oldest go first: the filter's next analysis should be as close to now as it can be.
    while (waiting_.size() > capacity_) {
      waiting_.pop_front();
      ++skipped_;
    }
    skipped = skipped_;
  }
  ready_.notify_one();
  return skipped;
}

std::optional<Frame> FrameMailbox::take() {
  std::unique_lock lock(mutex_);
  ready_.wait(lock, [this] { return closed_ || !waiting_.empty(); });
  if (waiting_.empty()) return std::nullopt;
  Frame frame = std::move(waiting_.front());
  waiting_.pop_front();
  return frame;
}

void FrameMailbox::close(bool dropWaiting) {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
    if (dropWaiting) {
      skipped_ += static_cast<long>(waiting_.size());
      waiting_.clear();
    }
  }
  ready_.notify_all();
}

long FrameMailbox::skipped() const {
  std::lock_guard lock(mutex_);
  return skipped_;
}

}  // namespace bcassim
