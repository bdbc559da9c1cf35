// CSV marker tracks and numeric tables: round trip with missing markers and line-numbered errors.
#include <gtest/gtest.h>

#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/CsvTruncate.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::TempDir;
using test::writeText;

TEST(MarkerTracks, RoundTripWithMissingMarker) {
  TempDir dir;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixX3d f0(3, 3), f1(3, 3);
  f0 << 0.1, 0.2, 0.3, 1.0 / 3.0, -0.5, 1e-7, 4, 5, 6;
  f1 << 0.11, 0.21, 0.31, nan, nan, nan, 4.5, 5.5, 6.5;
  {
    MarkerTrackWriter writer(dir.file("out/tracks.csv"));
    writer.write(0.0, f0);
    writer.write(0.01, f1);
  }
  const MarkerTracks tracks = readMarkerTracks(dir.file("out/tracks.csv"));
  ASSERT_EQ(tracks.numMarkers, 3);
  ASSERT_EQ(tracks.times, (std::vector<double>{0.0, 0.01}));
  ASSERT_EQ(tracks.frames.size(), 2u);
  EXPECT_EQ(tracks.frames[0], f0);
  EXPECT_TRUE(tracks.frames[1].row(1).array().isNaN().all());
  EXPECT_EQ(tracks.frames[1].row(0), f1.row(0));
  EXPECT_EQ(tracks.frames[1].row(2), f1.row(2));
}

TEST(MarkerTracks, FlushesEachFrame) {
  TempDir dir;
  MarkerTrackWriter writer(dir.file("t.csv"));
  writer.write(0.5, Eigen::MatrixX3d::Ones(2, 3));
  EXPECT_EQ(test::readText(dir.file("t.csv")), "time,marker,x,y,z\n0.5,0,1,1,1\n0.5,1,1,1,1\n");
}

// Resuming a run: rows after the checkpoint and a last line a crash cut short are dropped, the
// header kept, and writing continues after them.
TEST(MarkerTracks, ResumedWriterKeepsRowsUpToTheCheckpoint) {
  TempDir dir;
  writeText(dir.file("t.csv"), "time,marker,x,y,z\n0.1,0,1,1,1\n0.2,0,2,2,2\n0.3,0,3,3,3\n0.3");
  {
    MarkerTrackWriter writer(dir.file("t.csv"), 0.2);
    writer.write(0.3, Eigen::MatrixX3d::Constant(1, 3, 9.0));
  }
  EXPECT_EQ(test::readText(dir.file("t.csv")),
            "time,marker,x,y,z\n0.1,0,1,1,1\n0.2,0,2,2,2\n0.3,0,9,9,9\n");
  writeText(dir.file("u.csv"), "step,ms\n1,5\n2,6\n3,7");
  keepCsvRowsUpTo(dir.file("u.csv"), 10);
  EXPECT_EQ(test::readText(dir.file("u.csv")), "step,ms\n1,5\n2,6\n");
  EXPECT_THROW(keepCsvRowsUpTo(dir.file("missing.csv"), 1), InputError);
}

TEST(MarkerTracks, NanCoordinate) {
  TempDir dir;
  const std::string path =
      writeText(dir.file("tracks.csv"), "time,marker,x,y,z\n0,0,1,2,3\n0,1,1,2,nan\n");
  EXPECT_INPUT_ERROR(path + ":3: field z is not a finite number ('nan')", readMarkerTracks(path));
}

TEST(MarkerTracks, WrongColumnCount) {
  TempDir dir;
  const std::string path =
      writeText(dir.file("tracks.csv"), "time,marker,x,y,z\n\n0,0,1,2,3\n0,1,1,2\n");
  EXPECT_INPUT_ERROR(path + ":4: expected 5 fields (time,marker,x,y,z), got 4",
                     readMarkerTracks(path));
}

TEST(MarkerTracks, NonNumericField) {
  TempDir dir;
  const std::string path = writeText(dir.file("tracks.csv"), "0,0,1,2,3\n0,one,1,2,3\n");
  EXPECT_INPUT_ERROR(path + ":2: field 2 is not a number ('one')", readMarkerTracks(path));
}

TEST(MarkerTracks, TimesMustNotDecrease) {
  TempDir dir;
  const std::string path = writeText(dir.file("tracks.csv"),
                                     "time,marker,x,y,z\n0.1,0,1,2,3\n0.2,0,1,2,3\n0.15,0,1,2,3\n");
  EXPECT_INPUT_ERROR(path +
                         ":4: time 0.15 is earlier than 0.2 on line 3; expected "
                         "non-decreasing times",
                     readMarkerTracks(path));
}

TEST(MarkerTracks, MarkerTwiceInAFrame) {
  TempDir dir;
  const std::string path =
      writeText(dir.file("tracks.csv"), "time,marker,x,y,z\n0,0,1,2,3\n0,0,1,2,3\n");
  EXPECT_INPUT_ERROR(path +
                         ":3: marker 0 appears twice at time 0 (also line 2); expected one "
                         "row per marker and frame",
                     readMarkerTracks(path));
}

TEST(MarkerTracks, WrongHeader) {
  TempDir dir;
  const std::string path = writeText(dir.file("tracks.csv"), "t,id,x,y,z\n0,0,1,2,3\n");
  EXPECT_INPUT_ERROR(path + ": header is 't,id,x,y,z'; expected time,marker,x,y,z",
                     readMarkerTracks(path));
}

TEST(CsvTable, ReadsHeaderRowsAndSkipsComments) {
  TempDir dir;
  const std::string path = writeText(dir.file("traj.csv"),
                                     "# control point\r\n\"time\",x,y,z\r\n0,0,0,0\r\n"
                                     "0.5, 1e-3, -2, +3\r\n");
  const CsvTable table = readCsvTable(path);
  EXPECT_EQ(table.header, (std::vector<std::string>{"time", "x", "y", "z"}));
  Eigen::MatrixXd rows(2, 4);
  rows << 0, 0, 0, 0, 0.5, 1e-3, -2, 3;
  EXPECT_EQ(table.rows, rows);
  EXPECT_EQ(table.lines, (std::vector<int>{3, 4}));
  EXPECT_EQ(table.column("y"), 2);
  EXPECT_EQ(table.column("w"), -1);
}

TEST(CsvTable, FirstLineMixingNumbersAndWordsIsABadRowNotAHeader) {
  TempDir dir;
  const std::string path = writeText(dir.file("traj.csv"), "0,O.5,0,0\n1,0,0,0\n");
  EXPECT_INPUT_ERROR(path + ":1: field 2 is not a number ('O.5')", readCsvTable(path));
}

TEST(CsvTable, BadLine) {
  TempDir dir;
  const std::string path = writeText(dir.file("traj.csv"), "time,x,y,z\n0,0,0,0\n1,0,0\n");
  EXPECT_INPUT_ERROR(path + ":3: expected 4 fields (time,x,y,z), got 3", readCsvTable(path));
  const std::string inf = writeText(dir.file("inf.csv"), "time,x,y,z\n0,0,inf,0\n");
  EXPECT_INPUT_ERROR(inf + ":2: field y is not a finite number ('inf')", readCsvTable(inf));
  const std::string empty = writeText(dir.file("empty.csv"), "time,x,y,z\n");
  EXPECT_INPUT_ERROR(empty + ": no data rows; expected comma-separated numbers",
                     readCsvTable(empty));
}

}  // namespace
}  // namespace bcassim
