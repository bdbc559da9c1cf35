#include "bcassim/live/ThreadPriority.h"

#include <algorithm>
#include <cerrno>

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace bcassim {

bool yieldToRealTime(int niceIncrement) {
#if defined(__linux__)
  // On Linux a thread id names one thread for PRIO_PROCESS: only this thread changes.
  const auto tid = static_cast<id_t>(syscall(SYS_gettid));
  errno = 0;
  const int current = getpriority(PRIO_PROCESS, tid);
  if (current == -1 && errno != 0) return false;
  return setpriority(PRIO_PROCESS, tid, std::min(19, current + std::max(0, niceIncrement))) == 0;
#else
  (void)niceIncrement;
  return false;
#endif
}

}  // namespace bcassim
