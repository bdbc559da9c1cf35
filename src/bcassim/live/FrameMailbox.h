// The bounded queue of frames waiting for the filter: when more than `capacity` wait, the oldest
// are skipped on purpose and counted, so a filter that falls behind never builds a backlog.
#pragma once
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>

#include "bcassim/live/Frame.h"

namespace bcassim {

class FrameMailbox {
 public:
  // capacity >= 1 frames waiting (InputError otherwise).
  explicit FrameMailbox(int capacity);

  // Adds a frame, skipping the oldest waiting ones beyond the capacity; never waits for the
  // taker (the lock is held for a deque operation only). Returns the frames skipped so far.
  // A frame put after close() is skipped.
  long put(Frame frame);

  // The oldest waiting frame; waits while none is waiting and the mailbox is open. Empty once
  // the mailbox is closed and nothing waits.
  std::optional<Frame> take();

  // No more frames: take() returns what waits, then nothing. dropWaiting: the waiting frames are
  // skipped (and counted) instead.
  void close(bool dropWaiting);

  long skipped() const;

 private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Frame> waiting_;
  long skipped_ = 0;
  bool closed_ = false;
};

}  // namespace bcassim
