// One long-lived thread that runs the jobs handed to it one after another, each answered by a
// std::future: for work that recurs in the background all run long (the mean tangent's builds).
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>

namespace bcassim {

// Unlike std::async, which starts a thread per job, the jobs share one thread and so one malloc
// arena: memory a build frees stays where the next build looks for it, instead of new pages for
// every new thread (on LiTS-3 the first background builds took 7,000, 3,600 and 1,700 page
// faults and up to 4x the CPU of the later ones; docs/benchmarks.md §7). The destructor lets the
// job underway finish, drops the ones not started (their futures report broken_promise) and joins.
class BackgroundThread {
 public:
  BackgroundThread() : thread_([this] { run(); }) {}
  ~BackgroundThread() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
      jobs_.clear();
    }
    wake_.notify_one();
    thread_.join();
  }
  BackgroundThread(const BackgroundThread&) = delete;
  BackgroundThread& operator=(const BackgroundThread&) = delete;

  // Runs `job` after those handed over before; its result (or exception) comes through the future.
  template <class Job>
  std::future<std::invoke_result_t<Job&>> submit(Job job) {
    using Result = std::invoke_result_t<Job&>;
    auto task = std::make_shared<std::packaged_task<Result()>>(std::move(job));
    std::future<Result> result = task->get_future();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      jobs_.emplace_back([task] { (*task)(); });
    }
    wake_.notify_one();
    return result;
  }

 private:
  void run() {
    for (;;) {
      std::function<void()> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
        if (jobs_.empty()) return;  // stopping, nothing left
        job = std::move(jobs_.front());
        jobs_.pop_front();
      }
      job();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace bcassim
