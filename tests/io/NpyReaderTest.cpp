// NumPy .npy files: arrays written by NumPy read back exactly (when python3-numpy is there),
// hand-made headers for every malformed case with their exact messages, and the benchmark's
// real files when ../shared/data is present.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "bcassim/io/NpyReader.h"
#include "bcassim/io/PointReader.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::bytesOf;
using test::npyBytes;

TEST(NpyReader, HandWrittenFileReadsExactly) {
  test::TempDir dir;
  const std::string path = test::writeText(
      dir.file("a.npy"), npyBytes("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }",
                                  bytesOf<double>({1.5, -2.0, 0.25, 1e-300,
                                                   std::numeric_limits<double>::infinity(), 7.0})));
  const NpyArray a = readNpy(path);
  EXPECT_EQ(a.shape, (std::vector<std::int64_t>{2, 3}));
  EXPECT_EQ(a.dtype, "<f8");
  EXPECT_EQ(a.values, (std::vector<double>{1.5, -2.0, 0.25, 1e-300,
                                           std::numeric_limits<double>::infinity(), 7.0}));
  EXPECT_TRUE(a.integers.empty());
  EXPECT_FALSE(a.isInteger());
  // Version 2.0 (4-byte header length), double quotes, no trailing comma.
  const std::string v2 = test::writeText(
      dir.file("b.npy"), npyBytes("{\"descr\": \"<f8\", \"fortran_order\": False, \"shape\": (1,)}",
                                  bytesOf<double>({3.0}), 2));
  EXPECT_EQ(readNpy(v2).values, (std::vector<double>{3.0}));
  EXPECT_EQ(formatNpyShape(readNpy(v2).shape), "(1,)");
  EXPECT_EQ(formatNpyIndex({2, 3, 4}, 23), "(1, 2, 3)");
  EXPECT_EQ(formatNpyIndex({7}, 4), "(4,)");
}

// NumPy writes a transposed array in Fortran order and a big-endian dtype's bytes most
// significant first: both read back in C order as the same numbers.
TEST(NpyReader, FortranOrderAndBigEndianReadInCOrder) {
  test::TempDir dir;
  std::string path =
      test::writeText(dir.file("fortran.npy"),
                      npyBytes("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3), }",
                               bytesOf<double>({1, 2, 3, 4, 5, 6})));
  NpyArray a = readNpy(path);
  EXPECT_EQ(a.shape, (std::vector<std::int64_t>{2, 3}));
  EXPECT_EQ(a.values, (std::vector<double>{1, 3, 5, 2, 4, 6}));
  // Three axes: element (i, j, k) of shape (2, 3, 2) lies at i + 2 j + 6 k in Fortran order.
  std::string data;
  for (int f = 0; f < 12; ++f) data += bytesOf<double>({static_cast<double>(f)});
  path = test::writeText(
      dir.file("fortran3.npy"),
      npyBytes("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3, 2), }", data));
  a = readNpy(path);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 2; ++k)
        EXPECT_EQ(a.values[static_cast<size_t>(6 * i + 2 * j + k)], i + 2 * j + 6 * k);
  std::string big = bytesOf<double>({-2.5});
  std::reverse(big.begin(), big.end());
  path =
      test::writeText(dir.file("big.npy"),
                      npyBytes("{'descr': '>f8', 'fortran_order': False, 'shape': (1,), }", big));
  EXPECT_EQ(readNpy(path).values, (std::vector<double>{-2.5}));
  path = test::writeText(dir.file("bigi.npy"),
                         npyBytes("{'descr': '>i4', 'fortran_order': True, 'shape': (2, 1), }",
                                  std::string("\xff\xff\xff\xfe\x00\x00\x01\x02", 8)));
  a = readNpy(path);
  EXPECT_EQ(a.integers, (std::vector<std::int64_t>{-2, 258}));
  EXPECT_EQ(a.values, (std::vector<double>{-2, 258}));
}

TEST(NpyReader, MalformedFilesAreOneLineErrors) {
  test::TempDir dir;
  const std::string f8 = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }";
  auto write = [&](const std::string& name, const std::string& bytes) {
    return test::writeText(dir.file(name), bytes);
  };
  std::string p = write("magic.npy", "NUMPY\x01\x00 not numpy at all");
  EXPECT_INPUT_ERROR(p + ": not a .npy file; expected it to start with the magic string \\x93NUMPY",
                     readNpy(p));
  p = write("short.npy", std::string("\x93NUM", 4));
  EXPECT_INPUT_ERROR(p + ": not a .npy file; expected it to start with the magic string \\x93NUMPY",
                     readNpy(p));
  std::string bytes = npyBytes(f8, bytesOf<double>({1, 2, 3, 4, 5, 6}));
  bytes[6] = 4;
  p = write("version.npy", bytes);
  EXPECT_INPUT_ERROR(p + ": .npy format version 4.0; expected 1.0, 2.0 or 3.0", readNpy(p));
  bytes = npyBytes(f8, "");
  p = write("header.npy", bytes.substr(0, 40));
  EXPECT_INPUT_ERROR(p + ": header of 118 bytes but the file has 40 bytes; expected a complete "
                         ".npy header",
                     readNpy(p));
  p = write("truncated.npy", npyBytes(f8, bytesOf<double>({1, 2, 3, 4, 5})));
  EXPECT_INPUT_ERROR(p + ": data of 40 bytes; expected 48 bytes for shape (2, 3) of <f8",
                     readNpy(p));
  p = write("trailing.npy", npyBytes(f8, bytesOf<double>({1, 2, 3, 4, 5, 6, 7})));
  EXPECT_INPUT_ERROR(p + ": data of 56 bytes; expected 48 bytes for shape (2, 3) of <f8",
                     readNpy(p));
  p = write("huge.npy", npyBytes("{'descr': '<f8', 'fortran_order': False, 'shape': "
                                 "(4294967296, 4294967296), }",
                                 bytesOf<double>({1})));
  EXPECT_INPUT_ERROR(p + ": data of 8 bytes; expected more than 2^64 bytes for shape "
                         "(4294967296, 4294967296) of <f8",
                     readNpy(p));
  const std::string dtypes =
      "expected a float (f4, f8), integer (i1, i2, i4, i8, u1, u2, u4, u8) or bool (b1) dtype, "
      "little- or big-endian (e.g. <f8, >i4, |u1)";
  for (const char* descr : {"<c16", "<f2", "|f8", "<i3", ">b2", "<U3", "=f8"}) {
    p = write(
        "dtype.npy",
        npyBytes(fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': (1,), }}", descr),
                 bytesOf<double>({1})));
    EXPECT_INPUT_ERROR(p + ": dtype '" + descr + "' not supported; " + dtypes, readNpy(p));
  }
  p = write("structured.npy",
            npyBytes("{'descr': [('x', '<f8')], 'fortran_order': False, 'shape': (1,), }",
                     bytesOf<double>({1})));
  EXPECT_INPUT_ERROR(p + ": malformed .npy header: structured dtype (a list of fields); expected "
                         "a plain dtype such as '<f8'",
                     readNpy(p));
  p = write("noshape.npy",
            npyBytes("{'descr': '<f8', 'fortran_order': False, }", bytesOf<double>({1})));
  EXPECT_INPUT_ERROR(p + ": .npy header without 'shape'; expected the keys 'descr', "
                         "'fortran_order' and 'shape'",
                     readNpy(p));
  p = write("badshape.npy",
            npyBytes("{'descr': '<f8', 'fortran_order': False, 'shape': (2, -3), }", ""));
  EXPECT_INPUT_ERROR(p + ": malformed .npy header: 'shape' is '(2, -3)'; expected a tuple of "
                         "non-negative integers",
                     readNpy(p));
}

TEST(NpyReader, PointsMustBeNByThreeAndFinite) {
  test::TempDir dir;
  std::string p = test::writeText(
      dir.file("p.npy"), npyBytes("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }",
                                  bytesOf<double>({1, 2, 3, 4, 5, 6})));
  Eigen::MatrixX3d expected(2, 3);
  expected << 1, 2, 3, 4, 5, 6;
  EXPECT_EQ(readPoints(p), expected);
  p = test::writeText(dir.file("q.npy"),
                      npyBytes("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 2), }",
                               bytesOf<double>({1, 2, 3, 4, 5, 6})));
  EXPECT_INPUT_ERROR(p + ": array of shape (3, 2); expected (N, 3) points with N >= 1",
                     readPoints(p));
  p = test::writeText(dir.file("r.npy"),
                      npyBytes("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }",
                               bytesOf<double>({1, 2, 3, 4, std::nan(""), 6})));
  EXPECT_INPUT_ERROR(p + ": point 1 has a non-finite coordinate (nan); expected a finite number",
                     readPoints(p));
}

// /usr/bin/python3 with NumPy, or empty.
std::string numpyPython() {
  for (const char* python : {"/usr/bin/python3", "python3"})
    if (std::system((std::string(python) + " -c 'import numpy' > /dev/null 2>&1").c_str()) == 0)
      return python;
  return {};
}

TEST(NpyReader, ArraysWrittenByNumpyReadBackExactly) {
  const std::string python = numpyPython();
  if (python.empty()) GTEST_SKIP() << "python3 with numpy not found";
  test::TempDir dir;
  const std::string script = test::writeText(dir.file("write.py"), R"(
import numpy as np, sys
d = sys.argv[1] + '/'
np.save(d + 'f8.npy', np.arange(12, dtype='<f8').reshape(3, 4) * 0.5 - 1)
np.save(d + 'f4.npy', (np.arange(15, dtype='<f4') / 4).reshape(5, 3))
np.save(d + 'i4.npy', np.arange(-3, 4, dtype='<i4'))
np.save(d + 'i8.npy', (np.arange(8, dtype='<i8') * 10**12 - 5).reshape(2, 2, 2))
np.save(d + 'i2.npy', np.array([-32768, 32767], dtype='<i2'))
np.save(d + 'i1.npy', np.array([-128, 127], dtype='i1'))
np.save(d + 'u1.npy', np.array([0, 1, 254, 255], dtype='u1'))
np.save(d + 'u2.npy', np.array([65535], dtype='<u2'))
np.save(d + 'u4.npy', np.array([4294967295], dtype='<u4'))
np.save(d + 'u8.npy', np.array([2**63 - 1], dtype='<u8'))
np.save(d + 'u8big.npy', np.array([0, 2**63], dtype='<u8'))
np.save(d + 'b1.npy', np.array([True, False, True]))
np.save(d + 'scalar.npy', np.float64(2.5))
np.save(d + 'empty.npy', np.zeros((0, 3)))
np.save(d + 'fortran.npy', np.asfortranarray(np.arange(24, dtype='<f8').reshape(2, 3, 4)))
np.save(d + 'transposed.npy', (np.arange(15, dtype='<f8').reshape(3, 5) * 0.1).T)
np.save(d + 'big.npy', np.array([[1.5, -2.0, 3.25]], dtype='>f8'))
np.save(d + 'bigu2.npy', np.array([1, 65535], dtype='>u2'))
np.save(d + 'bigids.npy', np.arange(4, dtype='>i8').reshape(2, 2).T)
with open(d + 'v2.npy', 'wb') as f:
    np.lib.format.write_array(f, np.arange(6, dtype='<f8').reshape(2, 3), version=(2, 0))
)");
  ASSERT_EQ(std::system((python + " " + script + " " + dir.path()).c_str()), 0);
  auto read = [&](const std::string& name) { return readNpy(dir.file(name)); };

  NpyArray a = read("f8.npy");
  EXPECT_EQ(a.shape, (std::vector<std::int64_t>{3, 4}));
  for (int k = 0; k < 12; ++k) EXPECT_EQ(a.values[k], 0.5 * k - 1.0);
  a = read("f4.npy");
  EXPECT_EQ(a.dtype, "<f4");
  for (int k = 0; k < 15; ++k) EXPECT_EQ(a.values[k], k / 4.0);
  EXPECT_EQ(readPoints(dir.file("f4.npy")).rows(), 5);
  a = read("i4.npy");
  EXPECT_TRUE(a.isInteger());
  EXPECT_EQ(a.integers, (std::vector<std::int64_t>{-3, -2, -1, 0, 1, 2, 3}));
  a = read("i8.npy");
  EXPECT_EQ(a.shape, (std::vector<std::int64_t>{2, 2, 2}));
  for (int k = 0; k < 8; ++k) EXPECT_EQ(a.integers[k], k * 1000000000000LL - 5);
  EXPECT_EQ(read("i2.npy").integers, (std::vector<std::int64_t>{-32768, 32767}));
  EXPECT_EQ(read("i1.npy").integers, (std::vector<std::int64_t>{-128, 127}));
  EXPECT_EQ(read("u1.npy").integers, (std::vector<std::int64_t>{0, 1, 254, 255}));
  EXPECT_EQ(read("u2.npy").integers, (std::vector<std::int64_t>{65535}));
  EXPECT_EQ(read("u4.npy").integers, (std::vector<std::int64_t>{4294967295LL}));
  EXPECT_EQ(read("u8.npy").integers,
            (std::vector<std::int64_t>{std::numeric_limits<std::int64_t>::max()}));
  EXPECT_INPUT_ERROR(
      dir.file("u8big.npy") + ": entry (1,) is 9223372036854775808; expected a value below 2^63",
      read("u8big.npy"));
  EXPECT_EQ(read("b1.npy").integers, (std::vector<std::int64_t>{1, 0, 1}));
  a = read("scalar.npy");
  EXPECT_TRUE(a.shape.empty());
  EXPECT_EQ(a.values, (std::vector<double>{2.5}));
  a = read("empty.npy");
  EXPECT_EQ(a.shape, (std::vector<std::int64_t>{0, 3}));
  EXPECT_TRUE(a.values.empty());
  a = read("fortran.npy");
  EXPECT_EQ(a.shape, (std::vector<std::int64_t>{2, 3, 4}));
  for (int k = 0; k < 24; ++k) EXPECT_EQ(a.values[static_cast<size_t>(k)], k);
  // np.save(points.T) of a (3, N) array: (N, 3) points, row by row.
  const Eigen::MatrixX3d transposed = readPoints(dir.file("transposed.npy"));
  ASSERT_EQ(transposed.rows(), 5);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(transposed(i, j), (5 * j + i) * 0.1);
  EXPECT_EQ(read("big.npy").values, (std::vector<double>{1.5, -2.0, 3.25}));
  EXPECT_EQ(read("bigu2.npy").integers, (std::vector<std::int64_t>{1, 65535}));
  EXPECT_EQ(read("bigids.npy").integers, (std::vector<std::int64_t>{0, 2, 1, 3}));
  a = read("v2.npy");
  EXPECT_EQ(a.values, (std::vector<double>{0, 1, 2, 3, 4, 5}));
}

TEST(NpyReader, MestdaghBenchmarkFiles) {
  // Sizes stated in ../shared/data/mestdagh-liver/README.md.
  const std::string positions =
      test::sharedFile("mestdagh-liver/sequences/linear/s1/positions-default.npy");
  if (positions.empty()) GTEST_SKIP() << "mestdagh-liver data not found";
  const NpyArray p = readNpy(positions);
  EXPECT_EQ(p.shape, (std::vector<std::int64_t>{50, 3046, 3}));
  EXPECT_EQ(p.dtype, "<f8");
  const NpyArray forces =
      readNpy(test::sharedFile("mestdagh-liver/sequences/linear/s1/true-forces.npy"));
  EXPECT_EQ(forces.shape, (std::vector<std::int64_t>{50, 3}));
  EXPECT_EQ(readPoints(test::sharedFile("mestdagh-liver/sequences/linear/s1/pointclouds/pc00.txt"))
                .rows(),
            500);
}

}  // namespace
}  // namespace bcassim
