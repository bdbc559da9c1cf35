#include "bcassim/io/IndexListReader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/NpyReader.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {
namespace {

constexpr long long kMaxId = std::numeric_limits<int>::max();

std::vector<int> readTextIds(const std::string& path, bool commaSeparated) {
  io::TextLines in(path);
  std::vector<int> ids;
  bool firstDataLine = true;
  while (in.next()) {
    std::string_view line = in.line();
    line = io::trim(line.substr(0, line.find('#')));
    if (line.empty()) continue;
    const auto fields = commaSeparated ? io::splitCommas(line) : io::splitBlanks(line);
    if (commaSeparated && firstDataLine) {
      firstDataLine = false;
      double number = 0.0;
      if (std::none_of(fields.begin(), fields.end(),
                       [&](std::string_view f) { return io::parseDouble(f, number); }))
        continue;  // a header line
    }
    for (const std::string_view field : fields) {
      long long id = -1;
      if (!io::parseInt(field, id) || id < 0 || id > kMaxId)
        in.fail(fmt::format("expected a non-negative integer id, got '{}'", io::excerpt(field)));
      ids.push_back(static_cast<int>(id));
    }
  }
  return ids;
}

std::vector<int> readNpyIds(const std::string& path) {
  const NpyArray array = readNpy(path);
  const auto& s = array.shape;
  const bool listShape = s.size() == 1 || (s.size() == 2 && (s[0] == 1 || s[1] == 1));
  if (!listShape)
    throw InputError(
        fmt::format("{}: array of shape {}; expected a list of ids, (N,), (N, 1) or "
                    "(1, N)",
                    path, formatNpyShape(s)));
  if (array.dtype == "|b1")
    throw InputError(fmt::format("{}: dtype '|b1' (bool); expected integer ids", path));
  std::vector<int> ids(array.values.size());
  for (size_t k = 0; k < ids.size(); ++k) {
    const double v = array.values[k];
    const bool valid = array.isInteger()
                           ? array.integers[k] >= 0 && array.integers[k] <= kMaxId
                           : v >= 0.0 && v <= static_cast<double>(kMaxId) && std::floor(v) == v;
    if (!valid)
      throw InputError(fmt::format(
          "{}: entry {} is {}; expected a non-negative integer id below 2^31", path,
          formatNpyIndex(s, static_cast<std::int64_t>(k)),
          array.isInteger() ? fmt::format("{}", array.integers[k]) : fmt::format("{}", v)));
    ids[k] = static_cast<int>(array.isInteger() ? array.integers[k] : static_cast<long long>(v));
  }
  return ids;
}

}  // namespace

std::vector<int> readIndexList(const std::string& path) {
  const std::string ext = io::lowerExtension(path);
  if (ext != ".csv" && ext != ".txt" && ext != ".npy")
    throw InputError(
        fmt::format("{}: unsupported id list format '{}'; expected .csv, .txt or .npy", path, ext));
  io::requireReadableFile(path);
  std::vector<int> ids = ext == ".npy" ? readNpyIds(path) : readTextIds(path, ext == ".csv");
  if (ids.empty())
    throw InputError(
        fmt::format("{}: no ids; expected at least one non-negative integer id", path));
  return ids;
}

}  // namespace bcassim
