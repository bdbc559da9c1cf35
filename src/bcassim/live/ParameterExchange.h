// The hand-over of parameter sets from the filter thread to the real-time thread: a set is
// swapped whole, so a reader sees one published set or the next, never a mix of the two.
#pragma once
#include <memory>
#include <mutex>

#include "bcassim/live/ParameterSet.h"

namespace bcassim {

class ParameterExchange {
 public:
  // Starts with the prior; throws InputError if its shape is wrong (checkParameterSet).
  explicit ParameterExchange(ParameterSet prior);

  // The latest published set. The lock is held only for the copy of the pointer (a reference
  // count increment): a reader never waits for a filter step, only for another pointer copy.
  std::shared_ptr<const ParameterSet> latest() const;

  // Replaces the current set; throws InputError if its size differs from the prior's. Readers
  // holding the previous set keep it alive until they let it go.
  void publish(std::shared_ptr<const ParameterSet> set);

  long size() const { return size_; }

 private:
  // A mutex rather than std::atomic<std::shared_ptr>: libstdc++ 12 has the latter, but it is not
  // lock-free either (a lock bit in the pointer), and a plain mutex is what ThreadSanitizer
  // understands without annotations.
  mutable std::mutex mutex_;
  std::shared_ptr<const ParameterSet> current_;
  long size_;
};

}  // namespace bcassim
