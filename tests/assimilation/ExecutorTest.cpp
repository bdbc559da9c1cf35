// Parallel forecasts give the same bits as serial ones, every task runs once on its own worker,
// and firstSigmaPointAlone finishes the first forecast before any other starts.
#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <atomic>
#include <mutex>
#include <set>
#include <thread>

#include "assimilation/AssimilationTestModels.h"
#include "bcassim/Error.h"
#include "bcassim/assimilation/EtkfFilter.h"
#include "bcassim/assimilation/RoukfFilter.h"
#include "bcassim/assimilation/ThreadPoolExecutor.h"
#include "bcassim/assimilation/UkfFilter.h"

namespace bcassim {
namespace {
using testing::Oscillator;

StochasticState layout() {
  return StochasticState(Eigen::Vector2d(0.1, 0.0), Eigen::Vector2d::Constant(1e-3),
                         {{"k", 1.0, 1.0, ParameterTransform::exponential()},
                          {"unused", 2.0, 0.5, ParameterTransform::identity()}});
}

enum class Kind { Ukf, Roukf, Etkf };

// Means after every step of a 60-step run.
std::vector<Eigen::VectorXd> run(Kind kind, Executor& executor, bool firstAlone) {
  std::vector<Oscillator> models(executor.workers());
  std::vector<ForecastModel*> pointers;
  for (Oscillator& m : models) pointers.push_back(&m);
  std::unique_ptr<Filter> filter;
  if (kind == Kind::Ukf) {
    UkfOptions o;
    o.firstSigmaPointAlone = firstAlone;
    filter = std::make_unique<UkfFilter>(layout(), pointers, executor, o);
  } else if (kind == Kind::Roukf) {
    RoukfOptions o;
    o.firstSigmaPointAlone = firstAlone;
    filter = std::make_unique<RoukfFilter>(layout(), pointers, executor, o);
  } else {
    EtkfOptions o;
    o.firstSigmaPointAlone = firstAlone;
    o.members = 7;
    o.processVariance = Eigen::Vector4d(0, 0, 1e-4, 1e-4);
    filter = std::make_unique<EtkfFilter>(layout(), pointers, executor, o);
  }
  std::vector<Eigen::VectorXd> means;
  for (const Observation& y : testing::oscillatorFrames(4.0, 60, 0.002))
    means.push_back(filter->step(y).mean);
  return means;
}

TEST(Executor, ThreadPoolGivesBitIdenticalResultsToSerial) {
  for (Kind kind : {Kind::Ukf, Kind::Roukf, Kind::Etkf}) {
    SerialExecutor serial;
    ThreadPoolExecutor pool(2);
    const auto reference = run(kind, serial, false);
    for (bool firstAlone : {false, true}) {
      const auto serialRun = run(kind, serial, firstAlone);
      const auto parallelRun = run(kind, pool, firstAlone);
      for (std::size_t i = 0; i < reference.size(); ++i) {
        EXPECT_TRUE(serialRun[i] == reference[i]) << static_cast<int>(kind) << " step " << i;
        EXPECT_TRUE(parallelRun[i] == reference[i]) << static_cast<int>(kind) << " step " << i;
      }
    }
  }
}

TEST(Executor, ThreadPoolRunsEveryTaskOnceWithAValidWorker) {
  ThreadPoolExecutor pool(2);
  std::vector<std::atomic<int>> count(100);
  std::array<std::atomic<int>, 2> busy{};
  std::atomic<bool> overlap = false;
  pool.run(100, [&](int t, int w) {
    ASSERT_GE(w, 0);
    ASSERT_LT(w, 2);
    if (busy[w]++ != 0) overlap = true;  // one task at a time per worker
    std::this_thread::sleep_for(std::chrono::microseconds(200));
    --busy[w];
    ++count[t];
  });
  for (const auto& c : count) EXPECT_EQ(c.load(), 1);
  EXPECT_FALSE(overlap.load());
  EXPECT_THROW(pool.run(3,
                        [](int t, int) {
                          if (t == 1) throw NumericalError("diverged");
                        }),
               NumericalError);
  EXPECT_THROW(ThreadPoolExecutor(0), InputError);
}

// Logs the start and end of each forecast with the parameter it got; the first of a step under
// star sigma points is the mean.
class RecordingModel final : public ForecastModel {
 public:
  struct Event {
    bool start;
    double param;
  };
  RecordingModel(std::mutex& mutex, std::vector<Event>& log) : mutex_(mutex), log_(log) {}
  Eigen::Index stateSize() const override { return 0; }
  Eigen::Index observableSize() const override { return 1; }
  void forecast(const Eigen::VectorXd&, const Eigen::VectorXd& params, Eigen::VectorXd& newState,
                Eigen::VectorXd& predicted) override {
    record({true, params[0]});
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    newState.resize(0);
    predicted = params.head(1);
    record({false, params[0]});
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd&) override {}

 private:
  void record(Event e) {
    std::lock_guard lock(mutex_);
    log_.push_back(e);
  }
  std::mutex& mutex_;
  std::vector<Event>& log_;
};

TEST(Executor, FirstSigmaPointAloneFinishesBeforeTheOthersStart) {
  std::mutex mutex;
  std::vector<RecordingModel::Event> log;
  RecordingModel a(mutex, log), b(mutex, log);
  ThreadPoolExecutor pool(2);
  UkfOptions options;
  options.firstSigmaPointAlone = true;
  UkfFilter ukf(StochasticState({}, {}, {{"k", 3.0, 1.0, {}}, {"c", 1.0, 1.0, {}}}), {&a, &b}, pool,
                options);
  for (int step = 0; step < 3; ++step) {
    log.clear();
    const double mean = ukf.mean()[0];
    ukf.step(Observation::withSigma(Eigen::VectorXd::Constant(1, 3.5), 0.5));
    ASSERT_EQ(log.size(), 10u);  // 2 x (2n + 1) events, n = 2
    EXPECT_TRUE(log[0].start);
    EXPECT_FALSE(log[1].start);
    EXPECT_EQ(log[0].param, mean);
    EXPECT_EQ(log[1].param, mean);
  }
}

// A model that itself uses TBB, as a parallel FEM assembly does, and notices if a second forecast
// enters the same instance while the first waits for its inner loop.
class NestedTbbModel final : public ForecastModel {
 public:
  std::atomic<bool> reentered = false;
  Eigen::Index stateSize() const override { return 1; }
  Eigen::Index observableSize() const override { return 1; }
  void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                Eigen::VectorXd& newState, Eigen::VectorXd& predicted) override {
    if (inside_.exchange(true)) reentered = true;
    const double sum = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, 20000, 100), 0.0,
        [&](const tbb::blocked_range<int>& r, double acc) {
          for (int i = r.begin(); i != r.end(); ++i) acc += std::sin(i * params[0]) * 1e-6;
          return acc;
        },
        std::plus<>());
    newState = Eigen::VectorXd::Constant(1, 0.9 * state[0] + params[0] + 1e-9 * sum);
    predicted = newState;
    inside_ = false;
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd&) override {}

 private:
  std::atomic<bool> inside_ = false;
};

TEST(Executor, ForecastsThatUseTbbInsideNeverShareAModel) {
  NestedTbbModel a, b;
  ThreadPoolExecutor pool(2);
  EtkfOptions options;
  options.members = 16;
  EtkfFilter etkf(StochasticState(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 0.1),
                                  {{"p", 1.0, 0.5, {}}}),
                  {&a, &b}, pool, options);
  for (int i = 0; i < 20; ++i)
    etkf.step(Observation::withSigma(Eigen::VectorXd::Constant(1, 5.0), 0.1));
  EXPECT_FALSE(a.reentered.load());
  EXPECT_FALSE(b.reentered.load());
}

TEST(Executor, FiltersRefuseTooFewModels) {
  Oscillator one;
  ThreadPoolExecutor pool(2);
  EXPECT_THROW(RoukfFilter(layout(), {&one}, pool), InputError);
  testing::StaticSpring wrongSize;
  SerialExecutor serial;
  EXPECT_THROW(RoukfFilter(layout(), {&wrongSize}, serial), InputError);
}

}  // namespace
}  // namespace bcassim
