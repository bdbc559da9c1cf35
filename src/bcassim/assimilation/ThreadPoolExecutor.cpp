#include "bcassim/assimilation/ThreadPoolExecutor.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "bcassim/Error.h"

namespace bcassim {

struct ThreadPoolExecutor::Arena {
  explicit Arena(int threads) : arena(threads) {}
  tbb::task_arena arena;
};

ThreadPoolExecutor::ThreadPoolExecutor(int threads) : threads_(threads) {
  if (threads < 1)
    throw InputError(fmt::format("thread pool needs at least one thread, got {}", threads));
  arena_ = std::make_unique<Arena>(threads);
}

ThreadPoolExecutor::~ThreadPoolExecutor() = default;

void ThreadPoolExecutor::run(int n, const std::function<void(int task, int worker)>& task) {
  if (n <= 0) return;
  arena_->arena.execute([&] {
    // One forecast is a whole simulation step: grain 1 balances them across threads.
    tbb::parallel_for(
        tbb::blocked_range<int>(0, n, 1),
        [&](const tbb::blocked_range<int>& range) {
          // In an arena of T slots the thread index is in [0, T): it names the worker.
          const int worker = tbb::this_task_arena::current_thread_index();
          for (int t = range.begin(); t != range.end(); ++t)
            tbb::this_task_arena::isolate([&] { task(t, worker); });
        },
        tbb::simple_partitioner());
  });
}

}  // namespace bcassim
