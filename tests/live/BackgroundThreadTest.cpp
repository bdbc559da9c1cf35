// BackgroundThread: jobs run in order on one thread that outlives them, results and exceptions
// come back through the futures, and destruction ends the job underway and drops the rest.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "bcassim/BackgroundThread.h"

namespace bcassim {
namespace {

TEST(BackgroundThread, RunsEveryJobInOrderOnOneThreadThatIsNotTheCallers) {
  BackgroundThread worker;
  std::vector<int> order;  // written by the worker only, read after the futures
  std::vector<std::future<std::thread::id>> ids;
  for (int i = 0; i < 20; ++i)
    ids.push_back(worker.submit([&order, i] {
      order.push_back(i);
      return std::this_thread::get_id();
    }));
  std::vector<std::thread::id> seen;
  for (auto& f : ids) seen.push_back(f.get());
  ASSERT_EQ(order.size(), 20u);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(order[static_cast<size_t>(i)], i);
  for (const auto& id : seen) EXPECT_EQ(id, seen.front());
  EXPECT_NE(seen.front(), std::this_thread::get_id());
}

TEST(BackgroundThread, ResultsAndExceptionsComeThroughTheFutures) {
  BackgroundThread worker;
  std::future<int> answer = worker.submit([] { return 42; });
  std::future<int> failure = worker.submit([]() -> int { throw std::runtime_error("no tangent"); });
  std::future<int> after = worker.submit([] { return 7; });  // the thread survives a throw
  EXPECT_EQ(answer.get(), 42);
  try {
    failure.get();
    FAIL() << "the job's exception was not rethrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "no tangent");
  }
  EXPECT_EQ(after.get(), 7);
}

TEST(BackgroundThread, DestructionFinishesTheJobUnderwayAndDropsTheOthers) {
  std::atomic<bool> started{false}, release{false}, finished{false};
  std::future<void> underway, dropped;
  std::thread releaser;
  {
    BackgroundThread worker;
    underway = worker.submit([&] {
      started = true;
      while (!release) std::this_thread::yield();
      finished = true;
    });
    dropped = worker.submit([] { FAIL() << "a job queued behind a destruction ran"; });
    while (!started) std::this_thread::yield();
    releaser = std::thread([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      release = true;
    });
  }  // joins the worker: waits for the job underway
  releaser.join();
  EXPECT_TRUE(finished);
  EXPECT_NO_THROW(underway.get());
  try {
    dropped.get();
    FAIL() << "the dropped job's future did not report it";
  } catch (const std::future_error& e) {
    EXPECT_EQ(e.code(), std::future_errc::broken_promise);
  }
}

}  // namespace
}  // namespace bcassim
