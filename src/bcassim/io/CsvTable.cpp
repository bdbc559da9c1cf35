#include "bcassim/io/CsvTable.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {

int CsvTable::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  return it == header.end() ? -1 : static_cast<int>(it - header.begin());
}

namespace {

std::string unquote(std::string_view s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return std::string(s);
}

// A header has no numeric field; a first line mixing numbers and words is a bad data line.
bool isHeader(const std::vector<std::string_view>& fields) {
  double v = 0;
  return std::none_of(fields.begin(), fields.end(),
                      [&](std::string_view f) { return io::parseDouble(f, v); });
}

}  // namespace

CsvTable readCsvTable(const std::string& path) {
  io::TextLines in(path);
  CsvTable table;
  std::vector<double> values;
  size_t columns = 0;
  bool first = true;
  auto fieldName = [&](size_t k) {
    return k < table.header.size() && !table.header[k].empty() ? io::excerpt(table.header[k])
                                                               : fmt::format("{}", k + 1);
  };
  auto columnList = [&] {
    std::string list;
    for (size_t k = 0; k < table.header.size(); ++k) {
      if (k) list += ',';
      list += io::excerpt(table.header[k]);
    }
    return io::excerpt(list, 200);
  };
  while (in.next()) {
    const std::string_view line = io::trim(in.line());
    if (line.empty() || line.front() == '#') continue;
    const auto fields = io::splitCommas(line);
    if (first) {
      first = false;
      columns = fields.size();
      if (isHeader(fields)) {
        for (const auto f : fields) table.header.push_back(unquote(f));
        continue;
      }
    }
    if (fields.size() != columns)
      in.fail(table.header.empty()
                  ? fmt::format("expected {} fields, got {}", columns, fields.size())
                  : fmt::format("expected {} fields ({}), got {}", columns, columnList(),
                                fields.size()));
    for (size_t k = 0; k < columns; ++k) {
      double v = 0;
      if (!io::parseDouble(fields[k], v))
        in.fail(
            fmt::format("field {} is not a number ('{}')", fieldName(k), io::excerpt(fields[k])));
      if (!std::isfinite(v))
        in.fail(fmt::format("field {} is not a finite number ('{}')", fieldName(k),
                            io::excerpt(fields[k])));
      values.push_back(v);
    }
    table.lines.push_back(in.lineNumber());
  }
  if (table.lines.empty())
    throw InputError(fmt::format("{}: no data rows; expected comma-separated numbers", path));
  table.rows =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          values.data(), static_cast<Eigen::Index>(table.lines.size()),
          static_cast<Eigen::Index>(columns));
  return table;
}

}  // namespace bcassim
