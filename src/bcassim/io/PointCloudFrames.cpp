#include "bcassim/io/PointCloudFrames.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>

#include "bcassim/Error.h"
#include "bcassim/io/NpyReader.h"
#include "bcassim/io/PlyReader.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {

namespace {

namespace fs = std::filesystem;

// Natural order: runs of digits compare by value, so that pc2 comes before pc10.
bool naturalLess(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      size_t ei = i, ej = j;
      while (ei < a.size() && std::isdigit(static_cast<unsigned char>(a[ei]))) ++ei;
      while (ej < b.size() && std::isdigit(static_cast<unsigned char>(b[ej]))) ++ej;
      const std::string da = a.substr(i, ei - i), db = b.substr(j, ej - j);
      const size_t za = da.find_first_not_of('0'), zb = db.find_first_not_of('0');
      const std::string va = za == std::string::npos ? "" : da.substr(za);
      const std::string vb = zb == std::string::npos ? "" : db.substr(zb);
      if (va.size() != vb.size()) return va.size() < vb.size();
      if (va != vb) return va < vb;
      i = ei;
      j = ej;
      continue;
    }
    if (a[i] != b[j]) return a[i] < b[j];
    ++i;
    ++j;
  }
  return a.size() - i < b.size() - j;
}

// '*' matches any run of characters, everything else itself.
bool matches(const std::string& pattern, const std::string& name) {
  const size_t star = pattern.find('*');
  if (star == std::string::npos) return pattern == name;
  const std::string head = pattern.substr(0, star);
  if (name.compare(0, head.size(), head) != 0) return false;
  const std::string rest = pattern.substr(star + 1);
  for (size_t at = head.size(); at <= name.size(); ++at)
    if (matches(rest, name.substr(at))) return true;
  return false;
}

bool isCloudExtension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".txt" || ext == ".csv" || ext == ".npy" || ext == ".ply";
}

// The whole field as a number (NaN and inf included); nullopt otherwise.
std::optional<double> parseNumber(std::string_view field) {
  double v = 0.0;
  if (!io::parseDouble(field, v)) return std::nullopt;
  return v;
}

std::string fileName(const std::string& path) { return fs::path(path).filename().string(); }

// Rows whose three coordinates are finite; the others dropped, counted in one notice.
class FinitePoints {
 public:
  void add(const Eigen::Vector3d& p, int line) {
    if (p.allFinite()) {
      kept_.push_back(p);
      return;
    }
    if (dropped_++ == 0) firstLine_ = line;
  }
  Eigen::MatrixX3d take(const std::string& name, const std::string& where,
                        std::vector<std::string>& notices) {
    if (dropped_ > 0)
      notices.push_back(fmt::format("{}: {} point{} not finite ({} {} first), dropped", name,
                                    dropped_, dropped_ == 1 ? "" : "s", where, firstLine_));
    Eigen::MatrixX3d P(static_cast<Eigen::Index>(kept_.size()), 3);
    for (size_t i = 0; i < kept_.size(); ++i) P.row(static_cast<Eigen::Index>(i)) = kept_[i];
    kept_.clear();
    dropped_ = 0;
    return P;
  }

 private:
  std::vector<Eigen::Vector3d> kept_;
  int dropped_ = 0;
  int firstLine_ = 0;
};

Eigen::MatrixX3d readTextCloud(const std::string& path, std::vector<std::string>& notices) {
  io::TextLines in(path);
  FinitePoints points;
  while (in.next()) {
    const std::string_view line = in.line();
    const std::vector<std::string_view> fields = io::splitBlanks(line.substr(0, line.find('#')));
    if (fields.empty()) continue;
    if (fields.size() != 3)
      in.fail(fmt::format("expected 3 numbers (x y z, m), got {} fields", fields.size()));
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) {
      const auto v = parseNumber(fields[static_cast<size_t>(k)]);
      if (!v)
        in.fail(fmt::format("field {} is not a number ('{}')", "xyz"[k],
                            io::excerpt(fields[static_cast<size_t>(k)])));
      p(k) = *v;
    }
    points.add(p, in.lineNumber());
  }
  return points.take(fileName(path), "line", notices);
}

// A CSV's lines split into fields, the header (first line without a number) apart.
struct CsvLines {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;
  int column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  }
};

CsvLines readCsvLines(const std::string& path) {
  io::TextLines in(path);
  CsvLines csv;
  while (in.next()) {
    const std::string& line = in.line();
    if (io::isBlank(line) || line[0] == '#') continue;
    const std::vector<std::string_view> split = io::splitCommas(line);
    std::vector<std::string> fields(split.begin(), split.end());
    const bool anyNumber =
        std::any_of(split.begin(), split.end(), [](std::string_view f) { return parseNumber(f); });
    if (csv.rows.empty() && csv.header.empty() && !anyNumber) {
      csv.header = std::move(fields);
      continue;
    }
    const size_t expected = csv.header.empty()
                                ? (csv.rows.empty() ? fields.size() : csv.rows.front().size())
                                : csv.header.size();
    if (fields.size() != expected)
      in.fail(fmt::format("expected {} fields, got {}", expected, fields.size()));
    csv.rows.push_back(std::move(fields));
    csv.lines.push_back(in.lineNumber());
  }
  return csv;
}

double csvNumber(const CsvLines& csv, size_t row, int column, const std::string& path) {
  const std::string& field = csv.rows[row][static_cast<size_t>(column)];
  const auto v = parseNumber(field);
  if (!v)
    throw InputError(fmt::format("{}:{}: field {} is not a number ('{}')", path, csv.lines[row],
                                 csv.header.empty()
                                     ? std::to_string(column + 1)
                                     : io::excerpt(csv.header[static_cast<size_t>(column)]),
                                 io::excerpt(field)));
  return *v;
}

Eigen::MatrixX3d readCsvCloud(const std::string& path, std::vector<std::string>& notices) {
  const CsvLines csv = readCsvLines(path);
  int cols[3] = {0, 1, 2};
  if (!csv.header.empty()) {
    for (int k = 0; k < 3; ++k) cols[k] = csv.column(std::string(1, "xyz"[k]));
    if (cols[0] < 0 || cols[1] < 0 || cols[2] < 0)
      throw InputError(path + ":1: expected columns x,y,z (m) in the header");
  } else if (!csv.rows.empty() && csv.rows.front().size() != 3) {
    throw InputError(fmt::format("{}:{}: expected 3 fields (x,y,z, m), got {}", path,
                                 csv.lines.front(), csv.rows.front().size()));
  }
  FinitePoints points;
  for (size_t i = 0; i < csv.rows.size(); ++i) {
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) p(k) = csvNumber(csv, i, cols[k], path);
    points.add(p, csv.lines[i]);
  }
  return points.take(fileName(path), "line", notices);
}

Eigen::MatrixX3d readNpyCloud(const std::string& path, std::vector<std::string>& notices) {
  const NpyArray array = readNpy(path);
  const bool empty = array.shape.size() == 2 && array.shape[0] == 0;
  if (array.shape.size() != 2 || array.shape[1] != 3)
    throw InputError(fmt::format("{}: array of shape {}; expected (N, 3) points (m)", path,
                                 formatNpyShape(array.shape)));
  FinitePoints points;
  for (std::int64_t i = 0; !empty && i < array.shape[0]; ++i)
    points.add(Eigen::Vector3d(array.values[static_cast<size_t>(3 * i)],
                               array.values[static_cast<size_t>(3 * i + 1)],
                               array.values[static_cast<size_t>(3 * i + 2)]),
               static_cast<int>(i));
  return points.take(fileName(path), "row", notices);
}

// A PLY cloud's vertices (an RGB-D sensor's export; colours, normals and faces ignored).
Eigen::MatrixX3d readPlyCloud(const std::string& path, std::vector<std::string>& notices) {
  const Eigen::MatrixX3d V = io::readPly(path).V;
  FinitePoints points;
  for (Eigen::Index i = 0; i < V.rows(); ++i) points.add(V.row(i).transpose(), static_cast<int>(i));
  return points.take(fileName(path), "vertex", notices);
}

}  // namespace

std::vector<std::string> cloudFrameFiles(const std::string& folderOrPattern) {
  std::error_code ec;
  std::vector<std::string> files;
  const fs::path given(folderOrPattern);
  if (fs::is_directory(given, ec)) {
    for (const auto& entry : fs::directory_iterator(given, ec))
      if (entry.is_regular_file() && isCloudExtension(entry.path()))
        files.push_back(entry.path().string());
  } else {
    const std::string pattern = given.filename().string();
    const fs::path folder = given.has_parent_path() ? given.parent_path() : fs::path(".");
    if (pattern.find('*') == std::string::npos || !fs::is_directory(folder, ec))
      throw InputError(folderOrPattern +
                       ": expected a folder or a file pattern with '*' (e.g. clouds/pc*.txt)");
    for (const auto& entry : fs::directory_iterator(folder, ec))
      if (entry.is_regular_file() && matches(pattern, entry.path().filename().string()))
        files.push_back(entry.path().string());
  }
  if (files.empty())
    throw InputError(folderOrPattern + ": no point cloud file (.txt, .csv, .npy or .ply) found");
  std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
    return naturalLess(fs::path(a).filename().string(), fs::path(b).filename().string());
  });
  return files;
}

Eigen::MatrixX3d readCloudFile(const std::string& path, std::vector<std::string>& notices) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".txt") return readTextCloud(path, notices);
  if (ext == ".csv") return readCsvCloud(path, notices);
  if (ext == ".npy") return readNpyCloud(path, notices);
  if (ext == ".ply") return readPlyCloud(path, notices);
  throw InputError(
      fmt::format("{}: unsupported point cloud format '{}'; expected .txt, .csv, .npy or .ply",
                  path, io::excerpt(ext)));
}

std::vector<CloudFrame> readCloudCsv(const std::string& path, bool& byTime,
                                     std::vector<std::string>& notices) {
  const CsvLines csv = readCsvLines(path);
  const int frameColumn = csv.column("frame"), timeColumn = csv.column("time");
  int cols[3];
  for (int k = 0; k < 3; ++k) cols[k] = csv.column(std::string(1, "xyz"[k]));
  if ((frameColumn < 0 && timeColumn < 0) || cols[0] < 0 || cols[1] < 0 || cols[2] < 0)
    throw InputError(path + ":1: expected a header with columns frame (or time, s) and x,y,z (m)");
  if (frameColumn >= 0 && timeColumn >= 0)
    throw InputError(path + ":1: expected either a frame or a time column, not both");
  byTime = timeColumn >= 0;
  const int keyColumn = byTime ? timeColumn : frameColumn;
  const std::string name = fileName(path);

  std::vector<CloudFrame> frames;
  std::map<double, size_t> frameOf;
  std::vector<FinitePoints> points;
  std::vector<int> firstLine;
  double latest = -std::numeric_limits<double>::infinity();  // largest key so far
  std::optional<double> last;                                // key of the row before
  for (size_t i = 0; i < csv.rows.size(); ++i) {
    const double key = csvNumber(csv, i, keyColumn, path);
    if (!std::isfinite(key) || (!byTime && (key < 0 || key != std::floor(key))))
      throw InputError(fmt::format("{}:{}: {} must be {}, got {}", path, csv.lines[i],
                                   byTime ? "time" : "frame",
                                   byTime ? "a finite number (s)" : "an integer >= 0",
                                   io::excerpt(csv.rows[i][static_cast<size_t>(keyColumn)])));
    auto it = frameOf.find(key);
    if (it == frameOf.end()) {
      if (key < latest)
        notices.push_back(
            fmt::format("{}:{}: {} {:g}{} comes after {:g}{} (out of order); used at "
                        "its own {}",
                        name, csv.lines[i], byTime ? "time" : "frame", key, byTime ? " s" : "",
                        latest, byTime ? " s" : "", byTime ? "time" : "step"));
      it = frameOf.emplace(key, frames.size()).first;
      CloudFrame frame;
      frame.key = key;
      frame.name = byTime ? fmt::format("{} time {:g} s", name, key)
                          : fmt::format("{} frame {:g}", name, key);
      frames.push_back(std::move(frame));
      points.emplace_back();
      firstLine.push_back(csv.lines[i]);
    } else if (last && *last != key) {
      notices.push_back(
          fmt::format("{}:{}: {} {:g} continues after other frames; its rows are "
                      "joined to those of line {}",
                      name, csv.lines[i], byTime ? "time" : "frame", key, firstLine[it->second]));
    }
    latest = std::max(latest, key);
    last = key;
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) p(k) = csvNumber(csv, i, cols[k], path);
    points[it->second].add(p, csv.lines[i]);
  }
  if (frames.empty()) throw InputError(path + ": no point rows");
  for (size_t f = 0; f < frames.size(); ++f)
    frames[f].points = points[f].take(frames[f].name, "line", notices);
  return frames;
}

}  // namespace bcassim
