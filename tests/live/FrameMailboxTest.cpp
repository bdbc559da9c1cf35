// The bounded mailbox skips the oldest frames beyond its capacity, counts every frame it did not
// hand over, and hands over the rest in order.
#include <gtest/gtest.h>

#include "bcassim/Error.h"
#include "bcassim/live/FrameMailbox.h"

namespace bcassim {
namespace {

Frame frameNumber(long k) { return {k, 0.1 * static_cast<double>(k), Eigen::VectorXd::Zero(1)}; }

TEST(FrameMailbox, KeepsTheNewestFramesAndCountsTheOthers) {
  FrameMailbox mailbox(3);
  for (long k = 0; k < 10; ++k) EXPECT_EQ(mailbox.put(frameNumber(k)), k < 3 ? 0 : k - 2);
  EXPECT_EQ(mailbox.skipped(), 7);
  for (long k : {7, 8, 9}) {
    const std::optional<Frame> frame = mailbox.take();
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(frame->index, k);
  }
  mailbox.close(false);
  EXPECT_FALSE(mailbox.take().has_value());
  EXPECT_EQ(mailbox.skipped(), 7);
}

TEST(FrameMailbox, CloseDrainsOrDropsTheWaitingFrames) {
  FrameMailbox draining(5);
  draining.put(frameNumber(0));
  draining.put(frameNumber(1));
  draining.close(false);
  EXPECT_EQ(draining.take()->index, 0);
  EXPECT_EQ(draining.take()->index, 1);
  EXPECT_FALSE(draining.take().has_value());
  EXPECT_EQ(draining.skipped(), 0);

  FrameMailbox dropping(5);
  dropping.put(frameNumber(0));
  dropping.put(frameNumber(1));
  dropping.close(true);
  EXPECT_FALSE(dropping.take().has_value());
  EXPECT_EQ(dropping.skipped(), 2);
  EXPECT_EQ(dropping.put(frameNumber(2)), 3);  // after close: skipped too
}

TEST(FrameMailbox, CapacityBelowOneIsAnInputError) {
  try {
    FrameMailbox mailbox(0);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "LiveOptions.maxLagFrames: 0, expected at least 1 frame waiting for the filter");
  }
}

}  // namespace
}  // namespace bcassim
