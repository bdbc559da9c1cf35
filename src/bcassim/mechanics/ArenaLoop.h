// One loop of a few coarse tasks on a TBB arena of its own: the split kernels of a solve that has
// the cores to itself (ChunkedForces, CholeskyFactor's split sweeps).
#pragma once
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace bcassim {

// work(0), ..., work(count - 1) on the arena's threads, one task each (in order on the calling
// thread when the arena has one thread).
template <class Work>
void forEachOnArena(tbb::task_arena& arena, int count, Work&& work) {
  if (arena.max_concurrency() == 1) {
    for (int i = 0; i < count; ++i) work(i);
    return;
  }
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, count, 1),
        [&](const tbb::blocked_range<int>& range) {
          for (int i = range.begin(); i < range.end(); ++i) work(i);
        },
        tbb::simple_partitioner());
  });
}

}  // namespace bcassim
