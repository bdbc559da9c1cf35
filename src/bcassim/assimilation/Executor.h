// Runs the independent forecasts of one filter step, serially or on worker threads. Each worker
// index selects the ForecastModel instance the task must use.
#pragma once
#include <functional>

namespace bcassim {

// Contract: run(n, task) calls task(t, w) exactly once for every t in [0, n), with a worker index
// w in [0, workers()); one worker runs one task at a time, and every effect of every task is
// visible to the caller when run() returns. Tasks must be independent of each other (forecasts of
// different sigma points are); the order in which they run is unspecified. An exception thrown by
// a task is rethrown by run().
class Executor {
 public:
  virtual ~Executor() = default;
  virtual int workers() const = 0;
  virtual void run(int n, const std::function<void(int task, int worker)>& task) = 0;
};

// Runs every task on the calling thread, in order, as worker 0.
class SerialExecutor final : public Executor {
 public:
  int workers() const override { return 1; }
  void run(int n, const std::function<void(int task, int worker)>& task) override {
    for (int t = 0; t < n; ++t) task(t, 0);
  }
};

}  // namespace bcassim
