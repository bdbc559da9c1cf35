#include "bcassim/io/TextLines.h"

#include <fmt/format.h>

#include <charconv>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"

namespace bcassim::io {

TextLines::TextLines(const std::string& path) : path_(path) {
  requireReadableFile(path);
  in_.open(path, std::ios::binary);
  if (!in_) throw InputError(fmt::format("{}: cannot open file", path));
}

bool TextLines::next() {
  if (!std::getline(in_, line_)) return false;
  ++lineNumber_;
  if (!line_.empty() && line_.back() == '\r') line_.pop_back();
  return true;
}

void TextLines::fail(const std::string& what) const {
  throw InputError(fmt::format("{}:{}: {}", path_, lineNumber_, what));
}

namespace {
bool isBlankChar(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r'; }
}  // namespace

std::string_view trim(std::string_view s) {
  while (!s.empty() && isBlankChar(s.front())) s.remove_prefix(1);
  while (!s.empty() && isBlankChar(s.back())) s.remove_suffix(1);
  return s;
}

bool isBlank(std::string_view s) { return trim(s).empty(); }

std::vector<std::string_view> splitBlanks(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isBlankChar(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !isBlankChar(line[i])) ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

std::vector<std::string_view> splitCommas(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

bool parseDouble(std::string_view field, double& value) {
  // from_chars rejects a leading '+', which some writers emit.
  if (field.size() > 1 && field.front() == '+' && field[1] != '-') field.remove_prefix(1);
  if (field.empty()) return false;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  return ec == std::errc() && end == field.data() + field.size();
}

bool parseInt(std::string_view field, long long& value) {
  if (field.size() > 1 && field.front() == '+' && field[1] != '-') field.remove_prefix(1);
  if (field.empty()) return false;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  return ec == std::errc() && end == field.data() + field.size();
}

std::string excerpt(std::string_view field, size_t maxBytes) {
  std::string out;
  for (size_t i = 0; i < field.size() && i < maxBytes; ++i) {
    const auto c = static_cast<unsigned char>(field[i]);
    if (c >= 0x20 && c < 0x7f)
      out += static_cast<char>(c);
    else
      out += fmt::format("\\x{:02x}", c);
  }
  if (field.size() > maxBytes) out += "...";
  return out;
}

}  // namespace bcassim::io
