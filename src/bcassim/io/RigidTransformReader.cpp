#include "bcassim/io/RigidTransformReader.h"

#include <fmt/format.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <string_view>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/NpyReader.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {
namespace {

constexpr const char* kExpected =
    "expected the 4 rows of a 4 x 4 rigid transform (rotation and translation in m, last row 0 0 "
    "0 1)";

Eigen::Matrix4d readTextMatrix(const std::string& path) {
  io::TextLines in(path);
  Eigen::Matrix4d M;
  int rows = 0;
  while (in.next()) {
    std::string_view line = in.line();
    line = line.substr(0, line.find('#'));
    if (io::isBlank(line)) continue;
    if (rows == 4) in.fail(fmt::format("a fifth row; {}", kExpected));
    const auto fields =
        line.find(',') != std::string_view::npos ? io::splitCommas(line) : io::splitBlanks(line);
    if (fields.size() != 4)
      in.fail(fmt::format("expected 4 numbers (row {} of the 4 x 4 matrix), got {} fields",
                          rows + 1, fields.size()));
    for (int c = 0; c < 4; ++c) {
      double v = 0.0;
      if (!io::parseDouble(fields[c], v) || !std::isfinite(v))
        in.fail(
            fmt::format("field {} is not a finite number ('{}')", c + 1, io::excerpt(fields[c])));
      M(rows, c) = v;
    }
    ++rows;
  }
  if (rows < 4)
    throw InputError(fmt::format("{}: {} row{}; {}", path, rows, rows == 1 ? "" : "s", kExpected));
  return M;
}

Eigen::Matrix4d readNpyMatrix(const std::string& path) {
  const NpyArray array = readNpy(path);
  if (array.shape != std::vector<std::int64_t>{4, 4})
    throw InputError(fmt::format("{}: array of shape {}; expected (4, 4), a rigid transform", path,
                                 formatNpyShape(array.shape)));
  if (array.dtype == "|b1")
    throw InputError(fmt::format("{}: dtype '|b1' (bool); expected numbers", path));
  Eigen::Matrix4d M =
      Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(array.values.data());
  for (int k = 0; k < 16; ++k)
    if (!std::isfinite(M(k / 4, k % 4)))
      throw InputError(
          fmt::format("{}: element ({}, {}) is not finite; expected numbers", path, k / 4, k % 4));
  return M;
}

// The rigid motion M holds, or one line saying what else it is.
RigidTransform rigidFrom(const Eigen::Matrix4d& M, const std::string& path) {
  constexpr double kLastRowTolerance = 1e-6;
  const Eigen::RowVector4d last(0, 0, 0, 1);
  if ((M.row(3) - last).cwiseAbs().maxCoeff() > kLastRowTolerance)
    throw InputError(
        fmt::format("{}: the last row is {:g} {:g} {:g} {:g}; expected 0 0 0 1 (a "
                    "rigid transform, not a projection)",
                    path, M(3, 0), M(3, 1), M(3, 2), M(3, 3)));
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  const double det = R.determinant();
  if (!(det > 0))
    throw InputError(
        fmt::format("{}: the upper-left 3 x 3 has determinant {:.6g}; expected a "
                    "rotation (determinant 1, not a reflection)",
                    path, det));
  // Written to a few digits, a rotation is a rotation to ~1e-4; a scaling or a shear is far off.
  constexpr double kRotationTolerance = 1e-3;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d& s = svd.singularValues();
  if ((s.array() - 1.0).abs().maxCoeff() > kRotationTolerance) {
    if (s(0) - s(2) <= kRotationTolerance * s(0))
      throw InputError(
          fmt::format("{}: the upper-left 3 x 3 scales lengths by {:.6g}, not a "
                      "rotation (a change of units?); expected a rigid transform in "
                      "metres",
                      path, s(1)));
    throw InputError(
        fmt::format("{}: the upper-left 3 x 3 stretches lengths by {:.6g} to {:.6g}, "
                    "not a rotation; expected a rigid transform (rotation and "
                    "translation in m)",
                    path, s(2), s(0)));
  }
  RigidTransform t;
  t.rotation = svd.matrixU() * svd.matrixV().transpose();
  t.translation = M.topRightCorner<3, 1>();
  return t;
}

}  // namespace

RigidTransform readRigidTransform(const std::string& path) {
  const std::string ext = io::lowerExtension(path);
  if (ext != ".csv" && ext != ".txt" && ext != ".npy")
    throw InputError(
        fmt::format("{}: unsupported transform format '{}'; expected .csv, .txt or "
                    ".npy (a 4 x 4 matrix)",
                    path, ext));
  io::requireReadableFile(path);
  return rigidFrom(ext == ".npy" ? readNpyMatrix(path) : readTextMatrix(path), path);
}

}  // namespace bcassim
