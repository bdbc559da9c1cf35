// Failed output writes say why: a full disk (/dev/full) gives "No space left on device", a
// missing directory "No such file or directory", each on one line naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/ObjFormat.h"
#include "bcassim/io/PointCsvWriter.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

const std::string kFull = "/dev/full";
const std::string kNoSpace = "/dev/full: cannot write file (No space left on device)";

class OutputWriteErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kFull)) GTEST_SKIP() << "no /dev/full";
  }
};

TEST_F(OutputWriteErrors, MarkerTracksOnAFullDisk) {
  EXPECT_INPUT_ERROR(kNoSpace, MarkerTrackWriter writer(kFull));
}

TEST_F(OutputWriteErrors, PointCsvOnAFullDisk) {
  EXPECT_INPUT_ERROR(kNoSpace, writePointsCsv(kFull, Eigen::MatrixX3d::Zero(2, 3)));
}

TEST_F(OutputWriteErrors, ObjOnAFullDisk) {
  TriMesh mesh;
  mesh.V = Eigen::MatrixX3d::Identity(3, 3);
  mesh.F.resize(1, 3);
  mesh.F << 0, 1, 2;
  EXPECT_INPUT_ERROR(kNoSpace, writeObj(kFull, mesh));
}

TEST(OutputWriteErrorsOpen, MissingDirectoryUnderAFileNamesTheReason) {
  // The parent is a regular file, so neither the directory nor the file can be created.
  test::TempDir dir;
  const std::string blocker = test::writeText(dir.file("plain"), "x");
  const std::string path = blocker + "/tracks.csv";
  EXPECT_INPUT_ERROR(path + ": cannot create directory '" + blocker + "' (Not a directory)",
                     MarkerTrackWriter writer(path));
}

}  // namespace
}  // namespace bcassim
