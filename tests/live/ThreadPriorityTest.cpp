// The live loop's background threads give way to the real-time side (live/ThreadPriority.h).
#include <gtest/gtest.h>

#include <thread>

#include "bcassim/live/ThreadPriority.h"

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace bcassim {
namespace {

#if defined(__linux__)
int niceOfThisThread() { return getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid))); }

TEST(ThreadPriority, OnlyTheCallingThreadGivesWay) {
  const int before = niceOfThisThread();
  int inWorker = 0, inWorkersChild = 0;
  bool lowered = false;
  std::thread worker([&] {
    lowered = yieldToRealTime(5);
    inWorker = niceOfThisThread();
    std::thread child([&] { inWorkersChild = niceOfThisThread(); });
    child.join();
  });
  worker.join();
  ASSERT_TRUE(lowered);
  EXPECT_EQ(inWorker, std::min(19, before + 5));
  EXPECT_EQ(inWorkersChild, inWorker);    // inherited by the threads it starts
  EXPECT_EQ(niceOfThisThread(), before);  // the caller's thread only
}

TEST(ThreadPriority, NiceValueStopsAt19) {
  int after = 0;
  std::thread worker([&] {
    EXPECT_TRUE(yieldToRealTime(100));
    after = niceOfThisThread();
  });
  worker.join();
  EXPECT_EQ(after, 19);
}
#endif

}  // namespace
}  // namespace bcassim
