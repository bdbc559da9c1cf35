// The raw detections CSV (time,x,y,z, no ids): what is written reads back frame by frame, with
// an empty frame, a NaN detection and a time out of order kept for the tracker to report.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "bcassim/io/DetectionsCsv.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

TEST(DetectionsCsv, RoundTripKeepsFramesEmptyFramesNanAndOrder) {
  const auto dir = test::freshDir();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<TimedPoints> frames(4);
  frames[0] = {0.1, Eigen::MatrixX3d(2, 3)};
  frames[0].points << 0.1 / 3, 2, 3, -4e-7, 5, 6;
  frames[1] = {0.2, Eigen::MatrixX3d(0, 3)};
  frames[2] = {0.3, Eigen::MatrixX3d(1, 3)};
  frames[2].points << nan, 1, 2;
  frames[3] = {0.05, Eigen::MatrixX3d(1, 3)};  // out of order: a frame of its own
  frames[3].points << 7, 8, 9;
  const std::string path = (dir / "d.csv").string();
  writeDetectionsCsv(path, frames);
  const std::vector<TimedPoints> back = readDetectionsCsv(path);
  ASSERT_EQ(back.size(), frames.size());
  for (size_t f = 0; f < frames.size(); ++f) {
    EXPECT_EQ(back[f].time, frames[f].time);
    ASSERT_EQ(back[f].points.rows(), frames[f].points.rows()) << "frame " << f;
  }
  EXPECT_EQ(back[0].points, frames[0].points);  // round-trip precision
  EXPECT_TRUE(std::isnan(back[2].points(0, 0)));
  EXPECT_EQ(back[3].points, frames[3].points);
}

TEST(DetectionsCsv, RowsOfOneTimeFormOneFrameWithOrWithoutHeader) {
  const auto dir = test::freshDir();
  test::writeText(dir / "d.csv", "# camera 1\n0,1,2,3\n0,4,5,6\n\n1,7,8,9\n0,1,1,1\n");
  const std::vector<TimedPoints> f = readDetectionsCsv((dir / "d.csv").string());
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0].points.rows(), 2);
  EXPECT_EQ(f[1].points.rows(), 1);
  EXPECT_EQ(f[2].time, 0.0);  // a repeated time after another is a new frame
}

}  // namespace
}  // namespace bcassim
