// Point sets from text files (x y z per line) and node/vertex id lists from .csv, .txt and .npy,
// with their one-line errors.
#include <gtest/gtest.h>

#include <cstdint>

#include "bcassim/io/IndexListReader.h"
#include "bcassim/io/PointReader.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::bytesOf;

TEST(PointReader, TextFileOfXyzLines) {
  test::TempDir dir;
  const std::string path = test::writeText(dir.file("pc.txt"),
                                           "# point cloud, metres\n"
                                           "3.437967338101930587e-02 1.36e-02\t4.4e-01\n"
                                           "\n"
                                           "  -1 +2 3   # trailing comment\r\n");
  Eigen::MatrixX3d expected(2, 3);
  expected << 3.437967338101930587e-02, 1.36e-02, 4.4e-01, -1, 2, 3;
  EXPECT_EQ(readPoints(path), expected);
}

TEST(PointReader, TextFileErrorsNameTheLine) {
  test::TempDir dir;
  std::string p = test::writeText(dir.file("a.txt"), "1 2 3\n4 5\n");
  EXPECT_INPUT_ERROR(p + ":2: expected 3 numbers (x y z), got 2 fields", readPoints(p));
  p = test::writeText(dir.file("b.txt"), "1 2 3\n4 five 6\n");
  EXPECT_INPUT_ERROR(p + ":2: field y is not a finite number ('five')", readPoints(p));
  p = test::writeText(dir.file("c.txt"), "1 2 nan\n");
  EXPECT_INPUT_ERROR(p + ":1: field z is not a finite number ('nan')", readPoints(p));
  p = test::writeText(dir.file("d.txt"), "# nothing\n\n");
  EXPECT_INPUT_ERROR(p + ": no points; expected lines of x y z (m)", readPoints(p));
  p = test::writeText(dir.file("e.xyz"), "1 2 3\n");
  EXPECT_INPUT_ERROR(p + ": unsupported point set format '.xyz'; expected .vtk, .vtu, .vtp, "
                         ".ply, .csv, .txt or .npy",
                     readPoints(p));
}

TEST(IndexListReader, TextCsvAndNpyGiveTheIdsInOrder) {
  test::TempDir dir;
  const std::vector<int> expected{1929, 1947, 0, 5, 5};
  EXPECT_EQ(readIndexList(test::writeText(dir.file("a.txt"), "1929\n1947 0 # and\n\n5\t5\n")),
            expected);
  EXPECT_EQ(readIndexList(test::writeText(dir.file("b.csv"), "node\n1929,1947\n# c\n0, 5 ,5\n")),
            expected);
  EXPECT_EQ(readIndexList(test::writeText(dir.file("c.csv"), "1929,1947,0,5,5\n")), expected);
  EXPECT_EQ(readIndexList(test::writeText(
                dir.file("d.npy"),
                test::npyArray("<i8", "(5,)", bytesOf<std::int64_t>({1929, 1947, 0, 5, 5})))),
            expected);
  EXPECT_EQ(readIndexList(test::writeText(
                dir.file("e.npy"),
                test::npyArray("<i4", "(5, 1)", bytesOf<std::int32_t>({1929, 1947, 0, 5, 5})))),
            expected);
  EXPECT_EQ(readIndexList(test::writeText(
                dir.file("f.npy"),
                test::npyArray("<f8", "(1, 5)", bytesOf<double>({1929, 1947, 0, 5, 5})))),
            expected);
}

TEST(IndexListReader, BadIdsNameTheLineOrEntry) {
  test::TempDir dir;
  std::string p = test::writeText(dir.file("a.txt"), "1 2\n3 -1\n");
  EXPECT_INPUT_ERROR(p + ":2: expected a non-negative integer id, got '-1'", readIndexList(p));
  p = test::writeText(dir.file("b.txt"), "1 2.5\n");
  EXPECT_INPUT_ERROR(p + ":1: expected a non-negative integer id, got '2.5'", readIndexList(p));
  p = test::writeText(dir.file("c.csv"), "id\n1,,2\n");
  EXPECT_INPUT_ERROR(p + ":2: expected a non-negative integer id, got ''", readIndexList(p));
  p = test::writeText(dir.file("d.txt"), "3000000000\n");
  EXPECT_INPUT_ERROR(p + ":1: expected a non-negative integer id, got '3000000000'",
                     readIndexList(p));
  p = test::writeText(dir.file("e.csv"), "# only a comment\n");
  EXPECT_INPUT_ERROR(p + ": no ids; expected at least one non-negative integer id",
                     readIndexList(p));
  p = test::writeText(dir.file("f.npy"),
                      test::npyArray("<i8", "(3,)", bytesOf<std::int64_t>({4, -7, 1})));
  EXPECT_INPUT_ERROR(p + ": entry (1,) is -7; expected a non-negative integer id below 2^31",
                     readIndexList(p));
  p = test::writeText(dir.file("g.npy"),
                      test::npyArray("<f8", "(2, 1)", bytesOf<double>({4, 0.5})));
  EXPECT_INPUT_ERROR(p + ": entry (1, 0) is 0.5; expected a non-negative integer id below 2^31",
                     readIndexList(p));
  p = test::writeText(dir.file("h.npy"),
                      test::npyArray("<i8", "(2, 2)", bytesOf<std::int64_t>({1, 2, 3, 4})));
  EXPECT_INPUT_ERROR(p + ": array of shape (2, 2); expected a list of ids, (N,), (N, 1) or (1, N)",
                     readIndexList(p));
  p = test::writeText(dir.file("i.npy"), test::npyArray("<i8", "(0,)", ""));
  EXPECT_INPUT_ERROR(p + ": no ids; expected at least one non-negative integer id",
                     readIndexList(p));
  p = test::writeText(dir.file("j.json"), "[1, 2]");
  EXPECT_INPUT_ERROR(p + ": unsupported id list format '.json'; expected .csv, .txt or .npy",
                     readIndexList(p));
  EXPECT_INPUT_ERROR(dir.file("missing.txt") + ": cannot open file",
                     readIndexList(dir.file("missing.txt")));
}

TEST(IndexListReader, MestdaghBenchmarkLists) {
  // Counts stated in ../shared/data/mestdagh-liver/README.md and its .npy headers.
  const std::string fixed = test::sharedFile("mestdagh-liver/mesh-default/dirichlet-vertices.npy");
  if (fixed.empty()) GTEST_SKIP() << "mestdagh-liver data not found";
  EXPECT_EQ(readIndexList(fixed).size(), 106u);
  EXPECT_EQ(readIndexList(
                test::sharedFile("mestdagh-liver/sequences/linear/s1/forces-vertices-default.npy"))
                .size(),
            31u);
  const std::vector<int> tool = readIndexList(
      test::sharedFile("mestdagh-liver/sequences/linear/s1/tool-vertices-default.txt"));
  EXPECT_EQ(tool.front(), 1929);
  EXPECT_LT(*std::max_element(tool.begin(), tool.end()), 3046);  // mesh-default's node count
}

}  // namespace
}  // namespace bcassim
