#include "bcassim/io/PointReader.h"

#include <fmt/format.h>
#include <vtkDataSet.h>
#include <vtkDataSetReader.h>
#include <vtkNew.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <string_view>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/NpyReader.h"
#include "bcassim/io/PlyReader.h"
#include "bcassim/io/TextLines.h"
#include "bcassim/io/VtkSupport.h"

namespace bcassim {
namespace {

template <class Reader>
Eigen::MatrixX3d readVtkPoints(const std::string& path, bool legacy = false) {
  io::VtkErrorCapture capture;
  vtkNew<Reader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  legacy ? io::throwIfLegacyVtkError(capture, path, "cannot read VTK file")
         : io::throwIfVtkError(capture, path, "cannot read VTK file");
  vtkDataSet* data = vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  if (!data || data->GetNumberOfPoints() == 0)
    throw InputError(fmt::format("{}: no points read; expected a VTK dataset with points", path));
  Eigen::MatrixX3d V = io::pointsOf(data);
  io::requireFinitePoints(V, path);
  return V;
}

Eigen::MatrixX3d readCsvPoints(const std::string& path) {
  const CsvTable table = readCsvTable(path);
  int cols[3] = {0, 1, 2};
  if (!table.header.empty() && table.column("x") >= 0) {
    cols[0] = table.column("x");
    cols[1] = table.column("y");
    cols[2] = table.column("z");
    if (cols[1] < 0 || cols[2] < 0)
      throw InputError(
          fmt::format("{}: header names column x but not both y and z; expected "
                      "columns x,y,z",
                      path));
  } else if (table.rows.cols() != 3) {
    throw InputError(fmt::format("{}:{}: expected 3 fields (x,y,z), got {}", path,
                                 table.lines.front(), table.rows.cols()));
  }
  Eigen::MatrixX3d V(table.rows.rows(), 3);
  for (int k = 0; k < 3; ++k) V.col(k) = table.rows.col(cols[k]);
  return V;
}

Eigen::MatrixX3d readTextPoints(const std::string& path) {
  io::TextLines in(path);
  std::vector<double> values;
  constexpr const char* kAxes[3] = {"x", "y", "z"};
  while (in.next()) {
    std::string_view line = in.line();
    line = line.substr(0, line.find('#'));
    const auto fields = io::splitBlanks(line);
    if (fields.empty()) continue;
    if (fields.size() != 3)
      in.fail(fmt::format("expected 3 numbers (x y z), got {} fields", fields.size()));
    for (int k = 0; k < 3; ++k) {
      double v = 0.0;
      if (!io::parseDouble(fields[k], v) || !std::isfinite(v))
        in.fail(fmt::format("field {} is not a finite number ('{}')", kAxes[k],
                            io::excerpt(fields[k])));
      values.push_back(v);
    }
  }
  if (values.empty())
    throw InputError(fmt::format("{}: no points; expected lines of x y z (m)", path));
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      values.data(), static_cast<Eigen::Index>(values.size() / 3), 3);
}

Eigen::MatrixX3d readNpyPoints(const std::string& path) {
  const NpyArray array = readNpy(path);
  if (array.shape.size() != 2 || array.shape[1] != 3 || array.shape[0] < 1)
    throw InputError(fmt::format("{}: array of shape {}; expected (N, 3) points with N >= 1", path,
                                 formatNpyShape(array.shape)));
  if (array.dtype == "|b1")
    throw InputError(fmt::format("{}: dtype '|b1' (bool); expected coordinates as numbers", path));
  Eigen::MatrixX3d V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      array.values.data(), array.shape[0], 3);
  io::requireFinitePoints(V, path);
  return V;
}

Eigen::MatrixX3d readPlyPoints(const std::string& path) {
  Eigen::MatrixX3d V = io::readPly(path).V;
  if (V.rows() == 0) throw InputError(fmt::format("{}: no vertices; expected points", path));
  io::requireFinitePoints(V, path);
  return V;
}

}  // namespace

Eigen::MatrixX3d readPoints(const std::string& path) {
  const std::string ext = io::lowerExtension(path);
  if (ext != ".vtk" && ext != ".vtu" && ext != ".vtp" && ext != ".csv" && ext != ".txt" &&
      ext != ".npy" && ext != ".ply")
    throw InputError(
        fmt::format("{}: unsupported point set format '{}'; expected .vtk, .vtu, "
                    ".vtp, .ply, .csv, .txt or .npy",
                    path, ext));
  io::requireReadableFile(path);
  if (ext == ".ply") return readPlyPoints(path);
  if (ext == ".csv") return readCsvPoints(path);
  if (ext == ".txt") return readTextPoints(path);
  if (ext == ".npy") return readNpyPoints(path);
  if (ext == ".vtu") return readVtkPoints<vtkXMLUnstructuredGridReader>(path);
  if (ext == ".vtp") return readVtkPoints<vtkXMLPolyDataReader>(path);
  return readVtkPoints<vtkDataSetReader>(path, true);
}

}  // namespace bcassim
