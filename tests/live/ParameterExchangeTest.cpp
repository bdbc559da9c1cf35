// A parameter set is swapped whole: readers racing a writer through 10^5 swaps only ever see
// sets whose every entry equals their frame index, in non-decreasing order; sets of the wrong
// shape are refused.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/live/ParameterExchange.h"

namespace bcassim {
namespace {

constexpr int kSize = 8;  // mean of 8 and covariance of 64 entries

ParameterSet setNumber(long k) {
  const double v = static_cast<double>(k);
  return {Eigen::VectorXd::Constant(kSize, v), Eigen::MatrixXd::Constant(kSize, kSize, v), k};
}

bool consistent(const ParameterSet& set) {
  const double v = static_cast<double>(set.frame);
  return (set.mean.array() == v).all() && (set.covariance.array() == v).all();
}

struct ReaderResult {
  long reads = 0;
  long torn = 0;
  long backwards = 0;
  long lastFrame = -2;
};

TEST(ParameterExchange, SwapIsAtomicUnderConcurrentReads) {
  constexpr long kSwaps = 100000;
  ParameterExchange exchange(setNumber(0));
  std::atomic<bool> done{false};
  std::vector<ReaderResult> results(2);
  std::vector<std::thread> readers;
  for (ReaderResult& result : results) {
    readers.emplace_back([&exchange, &done, &result] {
      long previous = 0;
      auto check = [&] {
        const std::shared_ptr<const ParameterSet> set = exchange.latest();
        ++result.reads;
        if (!consistent(*set)) ++result.torn;
        if (set->frame < previous) ++result.backwards;
        previous = set->frame;
        result.lastFrame = set->frame;
      };
      while (!done.load(std::memory_order_acquire)) check();
      check();  // after the last swap: it must be visible
    });
  }
  std::thread writer([&] {
    for (long k = 1; k <= kSwaps; ++k)
      exchange.publish(std::make_shared<const ParameterSet>(setNumber(k)));
    done.store(true, std::memory_order_release);
  });
  writer.join();
  for (std::thread& reader : readers) reader.join();
  for (const ReaderResult& result : results) {
    EXPECT_GT(result.reads, 1);
    EXPECT_EQ(result.torn, 0);
    EXPECT_EQ(result.backwards, 0);
    EXPECT_EQ(result.lastFrame, kSwaps);
  }
}

TEST(ParameterExchange, RefusesSetsOfTheWrongShape) {
  ParameterExchange exchange(setNumber(0));
  ParameterSet longer = setNumber(3);
  longer.mean = Eigen::VectorXd::Zero(kSize + 1);
  try {
    exchange.publish(std::make_shared<const ParameterSet>(longer));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "live parameter set of frame 3: mean of 9 entries, expected 8 (the size of the "
                 "prior)");
  }
  ParameterSet badCovariance = setNumber(4);
  badCovariance.covariance = Eigen::MatrixXd::Zero(kSize, 2);
  try {
    exchange.publish(std::make_shared<const ParameterSet>(badCovariance));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "live parameter set of frame 4: covariance of 8 by 2, expected 8 by 8");
  }
  EXPECT_EQ(exchange.latest()->frame, 0);  // neither was published
  try {
    ParameterExchange empty(ParameterSet{});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "live prior parameter set: empty mean, expected at least one parameter");
  }
}

}  // namespace
}  // namespace bcassim
