// Shape checks of a parameter set, so that a filter publishing a set of the wrong size is stopped
// at the hand-over rather than read as garbage by the real-time side.
#include "bcassim/live/ParameterSet.h"

#include <string>

#include "bcassim/Error.h"

namespace bcassim {

void checkParameterSet(const ParameterSet& set, long expectedSize, const char* what) {
  const long n = set.mean.size();
  if (n == 0) throw InputError(std::string(what) + ": empty mean, expected at least one parameter");
  if (expectedSize >= 0 && n != expectedSize)
    throw InputError(std::string(what) + ": mean of " + std::to_string(n) + " entries, expected " +
                     std::to_string(expectedSize) + " (the size of the prior)");
  if (set.covariance.rows() != n || set.covariance.cols() != n)
    throw InputError(std::string(what) + ": covariance of " +
                     std::to_string(set.covariance.rows()) + " by " +
                     std::to_string(set.covariance.cols()) + ", expected " + std::to_string(n) +
                     " by " + std::to_string(n));
}

}  // namespace bcassim
