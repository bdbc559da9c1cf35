// The live engine on the linear-Gaussian toy: the synchronous run gives the exact posterior, the
// asynchronous run with a slow filter gives the same bits without ever making the real-time side
// wait, frames skipped on purpose are exactly those the filter did not analyse, and a filter's
// exception reaches finish().
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <future>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/live/LiveEngine.h"
#include "live/LinearGaussianToy.h"

namespace bcassim {
namespace {
using testing::LineToy;
using testing::SequentialKalman;

// What the real-time side published: the predicted observation H θ per frame, in order.
struct Published {
  std::vector<double> predicted;
};

RealTimeStep predictObservation(Published& published) {
  return predictThenPublish(
      [](const Frame& frame, const ParameterSet& parameters) {
        return (LineToy::observationRow(frame.time) * parameters.mean).value();
      },
      [&published](const Frame&, double predicted) { published.predicted.push_back(predicted); });
}

void expectClose(const ParameterSet& actual, const ParameterSet& expected, double tolerance) {
  EXPECT_EQ(actual.frame, expected.frame);
  EXPECT_LT((actual.mean - expected.mean).cwiseAbs().maxCoeff(), tolerance);
  EXPECT_LT((actual.covariance - expected.covariance).cwiseAbs().maxCoeff(), tolerance);
}

std::vector<long> firstFrames(long count) {
  std::vector<long> out;
  for (long k = 0; k < count; ++k) out.push_back(k);
  return out;
}

LiveOptions options(LiveMode mode, int maxLagFrames) {
  LiveOptions o;
  o.mode = mode;
  o.maxLagFrames = maxLagFrames;
  return o;
}

ParameterSet synchronousRun(const LineToy& toy, const std::vector<Frame>& frames) {
  SequentialKalman kalman(toy);
  Published published;
  LiveEngine engine(
      toy.prior(), predictObservation(published),
      [&kalman](const Frame& frame) { return kalman.update(frame); },
      options(LiveMode::Synchronous, 1));
  for (const Frame& frame : frames) engine.push(frame);
  engine.finish();
  return *engine.latest();
}

TEST(LiveEngine, SynchronousRunGivesTheClosedFormPosterior) {
  const LineToy toy;
  const std::vector<Frame> frames = toy.frames(90);
  SequentialKalman kalman(toy);
  Published published;
  LiveEngine engine(
      toy.prior(), predictObservation(published),
      [&kalman](const Frame& frame) { return kalman.update(frame); },
      options(LiveMode::Synchronous, 1));
  for (const Frame& frame : frames) engine.push(frame);
  const LiveSummary summary = engine.finish();

  expectClose(*engine.latest(), toy.posterior(frames, firstFrames(90)), 1e-12);
  EXPECT_EQ(summary.frames, 90);
  EXPECT_EQ(summary.analysed, 90);
  EXPECT_EQ(summary.skipped, 0);
  ASSERT_EQ(engine.records().size(), 90u);
  ASSERT_EQ(published.predicted.size(), 90u);
  for (long k = 0; k < 90; ++k) {
    const FrameRecord& record = engine.records()[k];
    EXPECT_EQ(record.frame, k);
    EXPECT_EQ(record.parametersFrame, k - 1);
    EXPECT_EQ(record.lagFrames, 0);
    EXPECT_EQ(record.skippedFrames, 0);
    // Frame k is predicted with the posterior over frames 0..k-1.
    const ParameterSet before = toy.posterior(frames, firstFrames(k));
    EXPECT_NEAR(published.predicted[k], LineToy::observationRow(frames[k].time) * before.mean,
                1e-12);
  }
}

TEST(LiveEngine, SlowFilterGivesTheSynchronousResultAndNeverBlocksTheRealTimeSide) {
  constexpr int kFrames = 40;
  constexpr auto kFilterDelay = std::chrono::milliseconds(25);
  const double delaySeconds = std::chrono::duration<double>(kFilterDelay).count();
  const LineToy toy;
  const std::vector<Frame> frames = toy.frames(kFrames);
  SequentialKalman kalman(toy);
  Published published;
  LiveEngine engine(
      toy.prior(), predictObservation(published),
      [&kalman, kFilterDelay](const Frame& frame) {
        std::this_thread::sleep_for(kFilterDelay);
        return kalman.update(frame);
      },
      options(LiveMode::Asynchronous, 1000));
  const Clock::time_point start = Clock::now();
  for (const Frame& frame : frames) {
    engine.push(frame);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // a camera faster than the filter
  }
  const double pushSeconds = secondsSince(start);
  const LiveSummary summary = engine.finish();

  // The same frames in the same order: the same bits as the synchronous run.
  const ParameterSet synchronous = synchronousRun(toy, frames);
  const ParameterSet& asynchronous = *engine.latest();
  EXPECT_EQ(asynchronous.frame, kFrames - 1);
  for (int i = 0; i < 2; ++i) EXPECT_EQ(asynchronous.mean(i), synchronous.mean(i));
  for (int i = 0; i < 4; ++i) EXPECT_EQ(asynchronous.covariance(i), synchronous.covariance(i));
  EXPECT_EQ(summary.analysed, kFrames);
  EXPECT_EQ(summary.skipped, 0);

  // The filter needs kFrames × 25 ms; waiting for it even every other frame would take half.
  EXPECT_LT(pushSeconds, 0.5 * kFrames * delaySeconds);
  long lagged = 0;
  ASSERT_EQ(engine.records().size(), static_cast<std::size_t>(kFrames));
  for (long k = 0; k < kFrames; ++k) {
    const FrameRecord& record = engine.records()[k];
    EXPECT_LT(record.publishSeconds, delaySeconds) << "frame " << k;
    EXPECT_LT(record.parametersFrame, k);
    EXPECT_EQ(record.lagFrames, k - 1 - record.parametersFrame);
    EXPECT_EQ(record.skippedFrames, 0);
    if (record.lagFrames > 0) ++lagged;
    // The prediction used exactly the set the record names.
    const ParameterSet used = toy.posterior(frames, firstFrames(record.parametersFrame + 1));
    EXPECT_NEAR(published.predicted[k], LineToy::observationRow(frames[k].time) * used.mean, 1e-12);
  }
  EXPECT_GT(lagged, 0);
}

// A filter step that waits at frame 0 until the test opens the gate, and says when it got there.
struct Gate {
  std::promise<void> reached;
  std::promise<void> open;
  std::shared_future<void> opened = open.get_future().share();
  void waitAt(const Frame& frame) {
    if (frame.index != 0) return;
    reached.set_value();
    opened.wait();
  }
};

TEST(LiveEngine, RealTimeSideRunsWhileTheFilterIsHeld) {
  constexpr int kFrames = 20;
  const LineToy toy;
  const std::vector<Frame> frames = toy.frames(kFrames);
  SequentialKalman kalman(toy);
  Gate gate;
  Published published;
  LiveEngine engine(
      toy.prior(), predictObservation(published),
      [&kalman, &gate](const Frame& frame) {
        gate.waitAt(frame);
        return kalman.update(frame);
      },
      options(LiveMode::Asynchronous, 100));
  std::future<void> pushing = std::async(std::launch::async, [&] {
    for (const Frame& frame : frames) engine.push(frame);
  });
  // If push waited for the filter, it could never finish while the filter is held.
  const std::future_status status = pushing.wait_for(std::chrono::seconds(20));
  gate.open.set_value();
  pushing.get();
  ASSERT_EQ(status, std::future_status::ready);
  const LiveSummary summary = engine.finish();
  EXPECT_EQ(summary.analysed, kFrames);
  for (long k = 0; k < kFrames; ++k) {
    EXPECT_EQ(engine.records()[k].parametersFrame, -1);  // nothing was analysed yet
    EXPECT_EQ(engine.records()[k].lagFrames, k);
  }
  expectClose(*engine.latest(), toy.posterior(frames, firstFrames(kFrames)), 1e-12);
}

TEST(LiveEngine, HeldFilterSkipsExactlyTheOldestWaitingFrames) {
  constexpr int kFrames = 30;
  const LineToy toy;
  const std::vector<Frame> frames = toy.frames(kFrames);
  SequentialKalman kalman(toy);
  Gate gate;
  std::vector<long> analysed;  // only the filter thread writes it, read after finish()
  Published published;
  LiveEngine engine(
      toy.prior(), predictObservation(published),
      [&](const Frame& frame) {
        gate.waitAt(frame);
        analysed.push_back(frame.index);
        return kalman.update(frame);
      },
      options(LiveMode::Asynchronous, 2));
  engine.push(frames[0]);
  gate.reached.get_future().wait();  // the filter holds frame 0
  for (int k = 1; k < kFrames; ++k) engine.push(frames[k]);
  gate.open.set_value();
  const LiveSummary summary = engine.finish();

  // Two frames may wait: of 1..29 only 28 and 29 are left to analyse after frame 0.
  EXPECT_EQ(analysed, (std::vector<long>{0, 28, 29}));
  EXPECT_EQ(summary.skipped, 27);
  EXPECT_EQ(summary.analysed, 3);
  for (long k = 0; k < kFrames; ++k)
    EXPECT_EQ(engine.records()[k].skippedFrames, std::max(0L, k - 2)) << "frame " << k;
  expectClose(*engine.latest(), toy.posterior(frames, analysed), 1e-12);
}

TEST(LiveEngine, SlowFilterSkipsAndAnalysesTheRestExactly) {
  constexpr int kFrames = 30;
  const LineToy toy;
  const std::vector<Frame> frames = toy.frames(kFrames);
  SequentialKalman kalman(toy);
  std::vector<long> analysed;
  Published published;
  LiveEngine engine(
      toy.prior(), predictObservation(published),
      [&](const Frame& frame) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        analysed.push_back(frame.index);
        return kalman.update(frame);
      },
      options(LiveMode::Asynchronous, 2));
  for (const Frame& frame : frames) engine.push(frame);  // far faster than 10 ms a frame
  const LiveSummary summary = engine.finish();

  EXPECT_GT(summary.skipped, 0);
  EXPECT_EQ(summary.skipped, kFrames - static_cast<long>(analysed.size()));
  EXPECT_EQ(summary.analysed, static_cast<long>(analysed.size()));
  ASSERT_FALSE(analysed.empty());
  EXPECT_EQ(analysed.back(), kFrames - 1);  // drained: the newest frame is never skipped
  for (std::size_t i = 1; i < analysed.size(); ++i) EXPECT_LT(analysed[i - 1], analysed[i]);
  for (long k = 1; k < kFrames; ++k)
    EXPECT_LE(engine.records()[k - 1].skippedFrames, engine.records()[k].skippedFrames);
  expectClose(*engine.latest(), toy.posterior(frames, analysed), 1e-12);
}

class LiveEngineModes : public ::testing::TestWithParam<LiveMode> {};

TEST_P(LiveEngineModes, FilterExceptionIsRethrownFromFinish) {
  const LineToy toy;
  const std::vector<Frame> frames = toy.frames(10);
  SequentialKalman kalman(toy);
  Published published;
  LiveEngine engine(
      toy.prior(), predictObservation(published),
      [&kalman](const Frame& frame) {
        if (frame.index == 3) throw std::runtime_error("filter diverged on frame 3");
        return kalman.update(frame);
      },
      options(GetParam(), 100));
  for (const Frame& frame : frames) engine.push(frame);
  try {
    engine.finish();
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "filter diverged on frame 3");
  }
  EXPECT_EQ(engine.records().size(), 10u);  // the real-time side went on
  expectClose(*engine.latest(), toy.posterior(frames, firstFrames(3)), 1e-12);
}

TEST_P(LiveEngineModes, SetOfTheWrongSizeFromTheFilterIsAnInputError) {
  const LineToy toy;
  SequentialKalman kalman(toy);
  Published published;
  LiveEngine engine(
      toy.prior(), predictObservation(published),
      [&kalman](const Frame& frame) {
        ParameterSet set = kalman.update(frame);
        if (frame.index == 1) set.mean = Eigen::VectorXd::Zero(3);
        return set;
      },
      options(GetParam(), 100));
  for (const Frame& frame : toy.frames(4)) engine.push(frame);
  try {
    engine.finish();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "live parameter set of frame 1: mean of 3 entries, expected 2 (the size of the "
                 "prior)");
  }
}

INSTANTIATE_TEST_SUITE_P(BothModes, LiveEngineModes,
                         ::testing::Values(LiveMode::Synchronous, LiveMode::Asynchronous),
                         [](const ::testing::TestParamInfo<LiveMode>& info) {
                           return info.param == LiveMode::Synchronous ? "Synchronous"
                                                                      : "Asynchronous";
                         });

TEST(LiveEngine, DestructionWithoutFinishStopsCleanly) {
  constexpr int kFrames = 20;
  const LineToy toy;
  const std::vector<Frame> frames = toy.frames(kFrames);
  std::atomic<int> calls{0};
  Gate gate;
  std::thread opener;
  {
    Published published;
    LiveEngine engine(
        toy.prior(), predictObservation(published),
        [&toy, &calls, &gate](const Frame& frame) {
          ++calls;
          gate.waitAt(frame);
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
          return toy.prior();
        },
        options(LiveMode::Asynchronous, 100));
    engine.push(frames[0]);
    gate.reached.get_future().wait();
    for (int k = 1; k < kFrames; ++k) engine.push(frames[k]);
    // Opened 20 ms after the destructor starts, so that it finds 19 frames waiting; analysing
    // them all would take 380 ms more.
    opener = std::thread([&gate] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      gate.open.set_value();
    });
  }  // the waiting frames are dropped, the filter thread joined
  opener.join();
  EXPECT_GE(calls.load(), 1);
  EXPECT_LT(calls.load(), kFrames);
  {
    Published published;
    LiveEngine failing(
        toy.prior(), predictObservation(published),
        [](const Frame&) -> ParameterSet { throw std::runtime_error("never seen"); },
        options(LiveMode::Asynchronous, 100));
    for (const Frame& frame : frames) failing.push(frame);
  }  // the filter's exception is dropped with the engine, not std::terminate
}

TEST(LiveEngine, BadInputIsAnInputError) {
  const LineToy toy;
  Published published;
  auto filter = [](const Frame&) { return ParameterSet{}; };
  try {
    LiveEngine engine(toy.prior(), predictObservation(published), filter,
                      options(LiveMode::Asynchronous, 0));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "LiveOptions.maxLagFrames: 0, expected at least 1 frame waiting for the filter");
  }
  ParameterSet wrongPrior = toy.prior();
  wrongPrior.covariance = Eigen::MatrixXd::Identity(3, 3);
  try {
    LiveEngine engine(wrongPrior, predictObservation(published), filter,
                      options(LiveMode::Synchronous, 1));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "live prior parameter set: covariance of 3 by 3, expected 2 by 2");
  }

  LiveEngine engine(toy.prior(), predictObservation(published), filter,
                    options(LiveMode::Synchronous, 1));
  Frame frame{1, 0.0, Eigen::VectorXd::Zero(1)};
  try {
    engine.push(frame);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "live frame: index 1, expected 0 (frames are numbered 0, 1, 2, ... as they come)");
  }
}

TEST(LiveEngine, FrameTimesMustIncrease) {
  const LineToy toy;
  Published published;
  SequentialKalman kalman(toy);
  LiveEngine engine(
      toy.prior(), predictObservation(published),
      [&kalman](const Frame& frame) { return kalman.update(frame); },
      options(LiveMode::Synchronous, 1));
  engine.push({0, 0.5, Eigen::VectorXd::Zero(1)});
  try {
    engine.push({1, 0.25, Eigen::VectorXd::Zero(1)});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "live frame 1: time 0.25 s, expected after the previous frame's 0.5 s");
  }
}

}  // namespace
}  // namespace bcassim
