#include "bcassim/io/DetectionsCsv.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {
namespace {

constexpr std::array<const char*, 4> kDetectionColumns = {"time", "x", "y", "z"};

bool sameTime(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

}  // namespace

std::vector<TimedPoints> readDetectionsCsv(const std::string& path) {
  io::TextLines in(path);
  std::vector<TimedPoints> frames;
  std::vector<double> coordinates;  // of the frame being read, row-major
  bool first = true, anyRow = false;
  auto closeFrame = [&] {
    if (frames.empty()) return;
    frames.back().points =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
            coordinates.data(), static_cast<Eigen::Index>(coordinates.size() / 3), 3);
    coordinates.clear();
  };
  while (in.next()) {
    const std::string_view line = io::trim(in.line());
    if (line.empty() || line.front() == '#') continue;
    const auto fields = io::splitCommas(line);
    if (first) {
      first = false;
      double v = 0.0;
      if (!io::parseDouble(fields.front(), v)) {  // a header
        bool expected = fields.size() == kDetectionColumns.size();
        for (size_t k = 0; expected && k < fields.size(); ++k)
          expected = fields[k] == kDetectionColumns[k];
        if (!expected)
          in.fail(fmt::format("header '{}'; expected time,x,y,z (s, m)", io::excerpt(line)));
        continue;
      }
    }
    if (fields.size() != kDetectionColumns.size())
      in.fail(fmt::format("expected 4 fields (time,x,y,z), got {}", fields.size()));
    double time = 0.0;
    if (!io::parseDouble(fields[0], time))
      in.fail(fmt::format("field time is not a number ('{}')", io::excerpt(fields[0])));
    const bool noDetection = fields[1].empty() && fields[2].empty() && fields[3].empty();
    Eigen::Vector3d p;
    for (int k = 0; k < 3 && !noDetection; ++k)
      if (!io::parseDouble(fields[k + 1], p[k]))
        in.fail(fmt::format("field {} is not a number ('{}')", kDetectionColumns[k + 1],
                            io::excerpt(fields[k + 1])));
    if (frames.empty() || !sameTime(frames.back().time, time)) {
      closeFrame();
      frames.push_back({time, {}});
    }
    if (!noDetection) coordinates.insert(coordinates.end(), p.data(), p.data() + 3);
    anyRow = true;
  }
  closeFrame();
  if (!anyRow) throw InputError(fmt::format("{}: no rows; expected time,x,y,z rows (s, m)", path));
  return frames;
}

void writeDetectionsCsv(const std::string& path, const std::vector<TimedPoints>& frames) {
  io::createParentDirectory(path);
  std::ofstream out(path);
  if (!out) io::throwWriteError(path);
  out << "time,x,y,z\n";
  fmt::memory_buffer buffer;
  for (const TimedPoints& frame : frames) {
    if (frame.points.rows() == 0) fmt::format_to(std::back_inserter(buffer), "{},,,\n", frame.time);
    for (Eigen::Index i = 0; i < frame.points.rows(); ++i)
      fmt::format_to(std::back_inserter(buffer), "{},{},{},{}\n", frame.time, frame.points(i, 0),
                     frame.points(i, 1), frame.points(i, 2));
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  out.flush();
  if (!out) io::throwWriteError(path);
}

}  // namespace bcassim
