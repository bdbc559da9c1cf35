// Executor on a fixed pool of threads (a TBB task arena): forecasts of sigma points run in
// parallel, each on the ForecastModel of the worker thread that picked it.
#pragma once
#include <memory>

#include "bcassim/assimilation/Executor.h"

namespace bcassim {

class ThreadPoolExecutor final : public Executor {
 public:
  // threads >= 1; throws InputError otherwise. The calling thread is one of them (worker 0).
  explicit ThreadPoolExecutor(int threads);
  ~ThreadPoolExecutor() override;
  int workers() const override { return threads_; }
  // A task may itself use TBB (a parallel assembly): it runs isolated, so a thread waiting inside
  // it never picks up another forecast that would share its worker index.
  void run(int n, const std::function<void(int task, int worker)>& task) override;

 private:
  struct Arena;
  int threads_;
  std::unique_ptr<Arena> arena_;
};

}  // namespace bcassim
