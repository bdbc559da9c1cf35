#include "bcassim/io/CsvTracks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/CsvTruncate.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {
namespace {

const std::vector<std::string> kColumns = {"time", "marker", "x", "y", "z"};
// A marker index is a small count; a huge one is a corrupt file, not a reason to allocate.
constexpr long long kMaxMarkers = 1000000;
// Dense frames up to this many marker rows are allowed however sparse the file (8 MiB of doubles).
constexpr long long kMinDenseRows = 1 << 20;

}  // namespace

MarkerTrackWriter::MarkerTrackWriter(const std::string& path) : path_(path) {
  io::createParentDirectory(path);
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) io::throwWriteError(path);
  out_ << "time,marker,x,y,z\n";
  out_.flush();
  if (!out_) io::throwWriteError(path);
}

MarkerTrackWriter::MarkerTrackWriter(const std::string& path, double until) : path_(path) {
  keepCsvRowsUpTo(path, until + 1e-9);
  out_.open(path, std::ios::binary | std::ios::app);
  if (!out_) io::throwWriteError(path);
}

void MarkerTrackWriter::write(double time, const Eigen::MatrixX3d& positions) {
  fmt::memory_buffer buffer;
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    if (positions.row(i).hasNaN()) continue;
    fmt::format_to(std::back_inserter(buffer), "{},{},{},{},{}\n", time, i, positions(i, 0),
                   positions(i, 1), positions(i, 2));
  }
  out_.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  out_.flush();
  if (!out_) io::throwWriteError(path_);
}

MarkerTracks readMarkerTracks(const std::string& path) {
  const CsvTable table = readCsvTable(path);
  if (!table.header.empty() && table.header != kColumns)
    throw InputError(fmt::format("{}: header is '{}'; expected time,marker,x,y,z", path,
                                 io::excerpt(fmt::format("{}", fmt::join(table.header, ",")), 80)));
  if (table.rows.cols() != 5)
    throw InputError(fmt::format("{}:{}: expected 5 fields (time,marker,x,y,z), got {}", path,
                                 table.lines.front(), table.rows.cols()));
  MarkerTracks tracks;
  std::vector<std::vector<std::pair<long long, Eigen::Index>>> frameRows;  // (marker, row)
  long long maxMarker = -1;
  for (Eigen::Index r = 0; r < table.rows.rows(); ++r) {
    const double time = table.rows(r, 0);
    const double marker = table.rows(r, 1);
    if (marker < 0 || marker != std::floor(marker) || marker >= kMaxMarkers)
      throw InputError(
          fmt::format("{}:{}: field marker is {}; expected an integer index in [0, "
                      "{})",
                      path, table.lines[r], marker, kMaxMarkers));
    if (!tracks.times.empty() && time < tracks.times.back())
      throw InputError(
          fmt::format("{}:{}: time {} is earlier than {} on line {}; expected "
                      "non-decreasing times",
                      path, table.lines[r], time, tracks.times.back(), table.lines[r - 1]));
    if (tracks.times.empty() || time > tracks.times.back()) {
      tracks.times.push_back(time);
      frameRows.emplace_back();
    }
    const long long m = static_cast<long long>(marker);
    for (const auto& [other, row] : frameRows.back())
      if (other == m)
        throw InputError(
            fmt::format("{}:{}: marker {} appears twice at time {} (also line {}); "
                        "expected one row per marker and frame",
                        path, table.lines[r], m, time, table.lines[row]));
    frameRows.back().emplace_back(m, r);
    maxMarker = std::max(maxMarker, m);
  }
  tracks.numMarkers = static_cast<int>(maxMarker + 1);
  // Frames are stored dense (a NaN row per missing marker): a few rows numbering markers far apart
  // would otherwise allocate frames x markers rows from a small file.
  const long long rows = table.rows.rows();
  const long long cells = static_cast<long long>(frameRows.size()) * tracks.numMarkers;
  if (cells > std::max(kMinDenseRows, 16 * rows))
    throw InputError(fmt::format(
        "{}: {} rows give {} frames of {} markers ({} marker rows, {} of them missing); expected "
        "markers numbered 0, 1, 2, ... with most present in every frame",
        path, rows, frameRows.size(), tracks.numMarkers, cells, cells - rows));
  for (const auto& rows : frameRows) {
    Eigen::MatrixX3d frame =
        Eigen::MatrixX3d::Constant(tracks.numMarkers, 3, std::numeric_limits<double>::quiet_NaN());
    for (const auto& [m, r] : rows) frame.row(m) = table.rows.row(r).tail<3>();
    tracks.frames.push_back(std::move(frame));
  }
  return tracks;
}

}  // namespace bcassim
