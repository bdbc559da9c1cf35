// Helpers of the io tests: a scratch directory, small meshes, capture of one-line errors, and
// (support/SharedData.h) the shared data files.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include "bcassim/Error.h"
#include "bcassim/mesh/TetMesh.h"
#include "bcassim/mesh/TriMesh.h"
#include "support/SharedData.h"

namespace bcassim::test {

// A fresh directory under the system temp directory, removed with its content at scope end.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("bcassim_io_test_" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

inline std::string writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

inline std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Bytes of a .npy file: magic, version `major`, the header dict padded with blanks to a multiple
// of 64 and ended by a newline, then `data`.
inline std::string npyBytes(const std::string& header, const std::string& data, int major = 1) {
  std::string dict = header;
  const size_t preamble = major == 1 ? 10 : 12;
  while ((preamble + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  std::string out = std::string("\x93NUMPY", 6) + static_cast<char>(major) + '\0';
  const size_t n = dict.size();
  out += static_cast<char>(n & 0xff);
  out += static_cast<char>((n >> 8) & 0xff);
  if (major != 1) out += std::string("\0\0", 2);
  return out + dict + data;
}

// A C-order array of dtype `descr` ("<f8") and `shape` ("(4, 4)") holding `data`.
inline std::string npyArray(const std::string& descr, const std::string& shape,
                            const std::string& data) {
  return npyBytes("{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }",
                  data);
}

// The bytes of `values` in this machine's (little-endian) order.
template <class T>
std::string bytesOf(std::initializer_list<T> values) {
  std::string s;
  for (T v : values) s.append(reinterpret_cast<const char*>(&v), sizeof v);
  return s;
}

// Unit cube split into 5 positively oriented tets (corner tets in regions 1, centre in 2);
// vertex i is at (i & 1, (i >> 1) & 1, (i >> 2) & 1).
inline TetMesh cubeMesh() {
  TetMesh mesh;
  mesh.V.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    mesh.V.row(i) << double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1);
  mesh.T.resize(5, 4);
  mesh.T << 0, 1, 2, 4,  //
      1, 3, 2, 7,        //
      1, 5, 7, 4,        //
      2, 7, 6, 4,        //
      1, 2, 4, 7;
  mesh.region.resize(5);
  mesh.region << 1, 1, 1, 1, 2;
  return mesh;
}

// Boundary of a tetrahedron, outward-facing, vertices first used in index order.
inline TriMesh tetSurface() {
  TriMesh mesh;
  mesh.V.resize(4, 3);
  mesh.V << 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.125, 0.0, 0.25, 0.0;
  mesh.F.resize(4, 3);
  mesh.F << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2;
  return mesh;
}

// The message of the InputError `f` throws; fails the test if it throws none.
inline std::string inputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

// Asserts that `f` throws an InputError with exactly `expected`, a single line.
#define EXPECT_INPUT_ERROR(expected, statement)                                     \
  do {                                                                              \
    const std::string message_ = ::bcassim::test::inputErrorOf([&] { statement; }); \
    EXPECT_EQ(message_, expected);                                                  \
    EXPECT_EQ(message_.find('\n'), std::string::npos) << message_;                  \
  } while (false)

}  // namespace bcassim::test
