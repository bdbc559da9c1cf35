#include "bcassim/io/PointReader.h"

#include <fmt/format.h>
#include <vtkDataSet.h>
#include <vtkDataSetReader.h>
#include <vtkNew.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/Files.h"
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

}  // namespace

Eigen::MatrixX3d readPoints(const std::string& path) {
  const std::string ext = io::lowerExtension(path);
  if (ext != ".vtk" && ext != ".vtu" && ext != ".vtp" && ext != ".csv")
    throw InputError(
        fmt::format("{}: unsupported point set format '{}'; expected .vtk, .vtu, "
                    ".vtp or .csv",
                    path, ext));
  io::requireReadableFile(path);
  if (ext == ".csv") return readCsvPoints(path);
  if (ext == ".vtu") return readVtkPoints<vtkXMLUnstructuredGridReader>(path);
  if (ext == ".vtp") return readVtkPoints<vtkXMLPolyDataReader>(path);
  return readVtkPoints<vtkDataSetReader>(path, true);
}

}  // namespace bcassim
