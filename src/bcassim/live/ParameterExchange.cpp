// The whole-set swap of ParameterExchange.h.
#include "bcassim/live/ParameterExchange.h"

#include <string>
#include <utility>

#include "bcassim/Error.h"

namespace bcassim {

ParameterExchange::ParameterExchange(ParameterSet prior) {
  checkParameterSet(prior, -1, "live prior parameter set");
  size_ = prior.mean.size();
  current_ = std::make_shared<const ParameterSet>(std::move(prior));
}

std::shared_ptr<const ParameterSet> ParameterExchange::latest() const {
  std::lock_guard lock(mutex_);
  return current_;
}

void ParameterExchange::publish(std::shared_ptr<const ParameterSet> set) {
  if (!set) throw InputError("live parameter set: null, expected a published set");
  const std::string what = "live parameter set of frame " + std::to_string(set->frame);
  checkParameterSet(*set, size_, what.c_str());
  // The old set is released after the lock, so that freeing it never delays a reader.
  std::shared_ptr<const ParameterSet> old;
  {
    std::lock_guard lock(mutex_);
    old = std::exchange(current_, std::move(set));
  }
}

}  // namespace bcassim
