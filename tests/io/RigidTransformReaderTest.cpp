// A rigid transform as a 4 x 4 matrix file (observations.frame_transform): the three forms read to
// the same motion, a matrix written to a few digits is taken as the nearest rotation, and what is
// not a rigid motion in metres is one exact line.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <vector>

#include "bcassim/io/RigidTransformReader.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::bytesOf;

RigidTransform someMotion() {
  RigidTransform t;
  t.rotation =
      Eigen::AngleAxisd(2.5, Eigen::Vector3d(-0.3, 0.8, 0.2).normalized()).toRotationMatrix();
  t.translation = Eigen::Vector3d(0.12, -0.034, 0.5);
  return t;
}

Eigen::Matrix4d homogeneous(const RigidTransform& t) {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.topLeftCorner<3, 3>() = t.rotation;
  M.topRightCorner<3, 1>() = t.translation;
  return M;
}

// The rows of M, each value as `format` writes it, separated by `separator`.
std::string rowsOf(const Eigen::Matrix4d& M, const char* separator,
                   const char* format = "{:.17g}") {
  std::string text;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      text += fmt::format(fmt::runtime(format), M(r, c)) + (c < 3 ? separator : "\n");
  return text;
}

void expectSameMotion(const RigidTransform& a, const RigidTransform& b, double tolerance) {
  EXPECT_LT((a.rotation - b.rotation).cwiseAbs().maxCoeff(), tolerance);
  EXPECT_LT((a.translation - b.translation).cwiseAbs().maxCoeff(), tolerance);
}

TEST(RigidTransformReader, CsvTxtAndNpyReadToTheSameMotion) {
  test::TempDir dir;
  const RigidTransform t = someMotion();
  const Eigen::Matrix4d M = homogeneous(t);
  // As `bcassim register` writes them, and as NumPy's savetxt does (with a comment line).
  expectSameMotion(readRigidTransform(test::writeText(dir.file("T.csv"), rowsOf(M, ","))), t,
                   1e-15);
  expectSameMotion(readRigidTransform(test::writeText(dir.file("T.txt"),
                                                      "# camera -> model\n\n" + rowsOf(M, " "))),
                   t, 1e-15);
  std::string data;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) data += bytesOf<double>({M(r, c)});
  expectSameMotion(
      readRigidTransform(test::writeText(dir.file("T.npy"), test::npyArray("<f8", "(4, 4)", data))),
      t, 1e-15);
}

// Five significant digits leave R^T R ~1e-5 off the identity: the nearest rotation is used, and
// it lies within the digits' precision of the true one.
TEST(RigidTransformReader, AMatrixWrittenToAFewDigitsIsTakenAsTheNearestRotation) {
  test::TempDir dir;
  const RigidTransform t = someMotion();
  const RigidTransform read =
      readRigidTransform(test::writeText(dir.file("T.txt"), rowsOf(homogeneous(t), " ", "{:.5f}")));
  EXPECT_LT((read.rotation.transpose() * read.rotation - Eigen::Matrix3d::Identity())
                .cwiseAbs()
                .maxCoeff(),
            1e-14);
  EXPECT_NEAR(read.rotation.determinant(), 1.0, 1e-14);
  expectSameMotion(read, t, 2e-5);
}

TEST(RigidTransformReader, WhatIsNotARigidMotionInMetresIsOneLine) {
  test::TempDir dir;
  const std::string expectedRows =
      "expected the 4 rows of a 4 x 4 rigid transform (rotation and translation in m, last row 0 "
      "0 0 1)";
  struct Case {
    std::string file, text, message;  // the message after "<path>"
  };
  const std::vector<Case> cases = {
      {"a.txt", "1 0 0 0\n0 1 0 0\n0 0 1\n0 0 0 1\n",
       ":3: expected 4 numbers (row 3 of the 4 x 4 matrix), got 3 fields"},
      {"b.csv", "1,0,0,0\n0,1,0,0\n0,0,1,nan\n0,0,0,1\n",
       ":3: field 4 is not a finite number ('nan')"},
      {"c.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n", ": 3 rows; " + expectedRows},
      {"d.txt", rowsOf(homogeneous(someMotion()), " ") + "0 0 0 1\n",
       ":5: a fifth row; " + expectedRows},
      {"e.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0.5 0 1\n",
       ": the last row is 0 0.5 0 1; expected 0 0 0 1 (a rigid transform, not a projection)"},
      {"f.txt", "-1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n",
       ": the upper-left 3 x 3 has determinant -1; expected a rotation (determinant 1, not a "
       "reflection)"},
      // A millimetre-to-metre scaling (or the reverse) is named as such.
      {"g.txt", "1000 0 0 0\n0 1000 0 0\n0 0 1000 0\n0 0 0 1\n",
       ": the upper-left 3 x 3 scales lengths by 1000, not a rotation (a change of units?); "
       "expected a rigid transform in metres"},
      {"h.txt", "1 0.2 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n",
       ": the upper-left 3 x 3 stretches lengths by 0.904988 to 1.10499, not a rotation; "
       "expected a rigid transform (rotation and translation in m)"},
      {"i.npy", test::npyArray("<f8", "(3, 4)", std::string(96, '\0')),
       ": array of shape (3, 4); expected (4, 4), a rigid transform"},
      {"j.mat", "1",
       ": unsupported transform format '.mat'; expected .csv, .txt or .npy (a 4 x 4 matrix)"},
  };
  for (const Case& c : cases) {
    const std::string path = test::writeText(dir.file(c.file), c.text);
    EXPECT_INPUT_ERROR(path + c.message, readRigidTransform(path));
  }
  EXPECT_INPUT_ERROR(dir.file("none.txt") + ": cannot open file",
                     readRigidTransform(dir.file("none.txt")));
}

}  // namespace
}  // namespace bcassim
