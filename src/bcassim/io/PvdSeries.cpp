#include "bcassim/io/PvdSeries.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/MeshWriter.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {
namespace {

bool isSafeName(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-';
  });
}

}  // namespace

PvdSeries::PvdSeries(const std::string& directory, const std::string& baseName)
    : directory_(directory), baseName_(baseName), parts_{""} {
  if (!isSafeName(baseName))
    throw std::invalid_argument(
        fmt::format("PvdSeries: base name '{}' must be letters, digits, "
                    "'_' or '-'",
                    baseName));
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  if (ec || !std::filesystem::is_directory(directory))
    throw InputError(fmt::format("{}: cannot create output directory{}", directory,
                                 ec ? fmt::format(" ({})", ec.message()) : ""));
}

std::vector<PvdEntry> readPvdIndex(const std::string& pvdPath) {
  std::ifstream in(pvdPath);
  if (!in) throw InputError(fmt::format("{}: cannot open", pvdPath));
  // Our own index: one <DataSet timestep=".." group="" part="N" file=".."/> per line.
  const std::regex entry(R"re(timestep="([^"]+)"[^>]*part="(\d+)"[^>]*file="([^"]+)")re");
  std::vector<PvdEntry> entries;
  std::smatch m;
  int lineNumber = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineNumber;
    if (!std::regex_search(line, m, entry)) continue;
    double time = 0;
    long long part = 0;
    // A damaged index must not end in std::stoi's exceptions or a part number sized like memory.
    if (!io::parseDouble(m[1].str(), time) || !io::parseInt(m[2].str(), part) || part > 1000)
      throw InputError(
          fmt::format("{}:{}: expected timestep=\"<s>\" and part=\"<0 to 1000>\", "
                      "got '{}'",
                      pvdPath, lineNumber, io::excerpt(io::trim(line), 120)));
    entries.push_back({time, static_cast<int>(part), m[3].str()});
  }
  return entries;
}

PvdSeries PvdSeries::resume(const std::string& directory, const std::string& baseName, int frames) {
  PvdSeries series(directory, baseName);
  const std::regex frameNumber(R"re(_(\d{6})\.vt[up]$)re");
  std::smatch f;
  for (const PvdEntry& e : readPvdIndex(series.pvdPath())) {
    if (!std::regex_search(e.file, f, frameNumber) || std::stoi(f[1].str()) >= frames) continue;
    if (e.part > 0) {  // <base>_<part>_<frame>.vtp: register the part name under its index
      if (e.file.size() < baseName.size() + 13 || e.file.compare(0, baseName.size(), baseName) != 0)
        throw InputError(fmt::format("{}: part file '{}' is not named {}_<part>_<frame>.vtp",
                                     series.pvdPath(), io::excerpt(e.file), baseName));
      const std::string name =
          e.file.substr(baseName.size() + 1, e.file.size() - baseName.size() - 1 - 11);
      if (static_cast<int>(series.parts_.size()) <= e.part) series.parts_.resize(e.part + 1);
      series.parts_[static_cast<size_t>(e.part)] = name;
    } else {
      ++series.numFrames_;
    }
    series.lastTime_ = e.time;
    series.entries_.push_back(e);
  }
  if (series.numFrames_ < frames)
    throw InputError(fmt::format("{}: lists {} frames, expected at least {} (the checkpoint's)",
                                 series.pvdPath(), series.numFrames_, frames));
  series.rewriteIndex();
  return series;
}

std::string PvdSeries::pvdPath() const {
  return (std::filesystem::path(directory_) / (baseName_ + ".pvd")).string();
}

int PvdSeries::addFrame(double time, const TetMesh& mesh, const Eigen::VectorXd& positions,
                        const FieldSet& fields) {
  if (!std::isfinite(time))
    throw std::invalid_argument(fmt::format("PvdSeries::addFrame: time {} is not finite", time));
  const int frame = numFrames_;
  const std::string file = fmt::format("{}_{:06d}.vtu", baseName_, frame);
  writeTetMesh((std::filesystem::path(directory_) / file).string(), mesh, positions, fields);
  ++numFrames_;
  lastTime_ = time;
  entries_.push_back({time, 0, file});
  rewriteIndex();
  return frame;
}

std::string PvdSeries::partFile(const std::string& part, const char* extension, int* partIndex) {
  if (numFrames_ == 0)
    throw std::invalid_argument("PvdSeries: addFrame must come before adding a part");
  if (!isSafeName(part))
    throw std::invalid_argument(
        fmt::format("PvdSeries: part name '{}' must be letters, digits, "
                    "'_' or '-'",
                    part));
  auto it = std::find(parts_.begin(), parts_.end(), part);
  if (it == parts_.end()) it = parts_.insert(parts_.end(), part);
  *partIndex = static_cast<int>(it - parts_.begin());
  return fmt::format("{}_{}_{:06d}{}", baseName_, part, numFrames_ - 1, extension);
}

void PvdSeries::addPoints(const std::string& part, const Eigen::MatrixX3d& points,
                          const FieldSet& fields) {
  int index = 0;
  const std::string file = partFile(part, ".vtp", &index);
  writePointCloud((std::filesystem::path(directory_) / file).string(), points, fields);
  entries_.push_back({lastTime_, index, file});
  rewriteIndex();
}

void PvdSeries::addPolyLines(const std::string& part, const Eigen::MatrixX3d& points,
                             const Eigen::MatrixX2i& segments, const FieldSet& fields) {
  int index = 0;
  const std::string file = partFile(part, ".vtp", &index);
  writePolyLines((std::filesystem::path(directory_) / file).string(), points, segments, fields);
  entries_.push_back({lastTime_, index, file});
  rewriteIndex();
}

void PvdSeries::rewriteIndex() const {
  fmt::memory_buffer xml;
  auto out = std::back_inserter(xml);
  fmt::format_to(out,
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                 "  <Collection>\n");
  for (const Entry& e : entries_)
    fmt::format_to(out, "    <DataSet timestep=\"{}\" group=\"\" part=\"{}\" file=\"{}\"/>\n",
                   e.time, e.part, e.file);
  fmt::format_to(out, "  </Collection>\n</VTKFile>\n");

  // Written beside and renamed over the index, so a reader never sees a half-written file.
  const std::string path = pvdPath();
  const std::string temporary = path + ".tmp";
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    file.write(xml.data(), static_cast<std::streamsize>(xml.size()));
    file.close();
    if (!file) {
      const int error = errno;
      std::remove(temporary.c_str());  // the index of the run stays as it was
      errno = error;
      io::throwWriteError(temporary);
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw OutputError(fmt::format("{}: cannot write file ({})", path, ec.message()));
  }
}

}  // namespace bcassim
