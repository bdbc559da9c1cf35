// The legacy format as VTK 9.1's vtkDataReader reads it: whitespace-separated keywords and ASCII
// values, or big-endian binary values after a keyword line; arrays may be followed by a METADATA
// block ending at a blank line. Counts come before data, so each is checked against the bytes left.
#include "bcassim/io/LegacyVtkReader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <optional>
#include <string_view>
#include <type_traits>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"
#include "bcassim/io/VtkCellTypes.h"
#include "bcassim/io/VtkScalarValues.h"

namespace bcassim::io {
namespace {

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// A data type name of the legacy format: a numeric type, a packed bit array, or strings.
struct DataType {
  enum Kind { kNumeric, kBit, kString } kind = kNumeric;
  VtkScalar scalar = VtkScalar::kFloat64;
};

std::optional<DataType> dataTypeNamed(std::string_view name) {
  const std::string n = lower(name);
  using S = VtkScalar;
  static const std::pair<const char*, S> kNumericTypes[] = {{"char", S::kInt8},
                                                            {"signed_char", S::kInt8},
                                                            {"unsigned_char", S::kUInt8},
                                                            {"short", S::kInt16},
                                                            {"unsigned_short", S::kUInt16},
                                                            {"int", S::kInt32},
                                                            {"unsigned_int", S::kUInt32},
                                                            {"long", S::kInt64},
                                                            {"unsigned_long", S::kUInt64},
                                                            {"vtktypeint64", S::kInt64},
                                                            {"vtktypeuint64", S::kUInt64},
                                                            {"vtkidtype", S::kInt32},
                                                            {"float", S::kFloat32},
                                                            {"double", S::kFloat64}};
  for (const auto& [typeName, scalar] : kNumericTypes)
    if (n == typeName) return DataType{DataType::kNumeric, scalar};
  if (n == "bit") return DataType{DataType::kBit, VtkScalar::kUInt8};
  if (n == "string" || n == "utf8_string") return DataType{DataType::kString, VtkScalar::kUInt8};
  return std::nullopt;
}

// VTK writes names with blanks and other special characters as %XX.
std::string decodeName(std::string_view name) {
  std::string out;
  for (size_t i = 0; i < name.size(); ++i) {
    if (name[i] == '%' && i + 2 < name.size() &&
        std::isxdigit(static_cast<unsigned char>(name[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(name[i + 2]))) {
      out += static_cast<char>(std::stoi(std::string(name.substr(i + 1, 2)), nullptr, 16));
      i += 2;
    } else {
      out += name[i];
    }
  }
  return out;
}

struct Token {
  std::string_view text;
  size_t at = 0;  // byte offset
  int line = 0;
};

// The cell blocks of the two dataset kinds: what a cell is called in messages and the least
// point count meaningful for it (unstructured grids check each cell against its type instead).
struct CellBlock {
  const char* keyword;
  const char* cellWord;
  int minPoints;
};
constexpr CellBlock kGridCells = {"CELLS", "cell", 1};
constexpr CellBlock kPolyBlocks[] = {{"VERTICES", "vertex cell", 1},
                                     {"LINES", "line", 2},
                                     {"POLYGONS", "polygon", 3},
                                     {"TRIANGLE_STRIPS", "triangle strip", 3}};

class LegacyParser {
 public:
  LegacyParser(std::string_view bytes, std::string source, VtkDataset::Kind expected)
      : data_(bytes), expected_(expected) {
    out_.kind = expected;
    out_.source = std::move(source);
  }

  VtkDataset parse() {
    header();
    std::optional<Token> typesToken;
    std::vector<unsigned char> types;
    while (std::optional<Token> t = nextToken()) {
      const std::string keyword = lower(t->text);
      if (keyword == "field") {
        readField(false);
      } else if (keyword == "points") {
        readPoints(*t);
      } else if (keyword == "cell_data" || keyword == "point_data") {
        readAttributes(*t);
        break;  // the attribute sections run to the end of the file, as in VTK
      } else if (isGrid() && keyword == "cells") {
        if (haveCells_) fail(*t, "a second CELLS section; expected one");
        readCells(*t, kGridCells, out_.cells);
        haveCells_ = true;
      } else if (isGrid() && keyword == "cell_types") {
        if (typesToken) fail(*t, "a second CELL_TYPES section; expected one");
        typesToken = *t;
        readCellTypes(types);
      } else if (const CellBlock* block = polyBlockNamed(keyword)) {
        VtkCells& cells = polyCells(*block);
        if (cells.size() > 0 || cells.offsets.size() != 1)
          fail(*t, fmt::format("a second {} section; expected one", block->keyword));
        readCells(*t, *block, cells);
      } else {
        fail(*t, fmt::format("unknown keyword '{}'; expected {}", excerpt(t->text),
                             isGrid() ? "POINTS, CELLS, CELL_TYPES, CELL_DATA, POINT_DATA or FIELD"
                                      : "POINTS, VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS, "
                                        "CELL_DATA, POINT_DATA or FIELD"));
      }
    }
    if (numPoints_ < 0)
      throw InputError(fmt::format("{}: no POINTS section; expected the points of the {}",
                                   out_.source, isGrid() ? "grid" : "surface"));
    if (isGrid()) finishGridCells(typesToken, types);
    return std::move(out_);
  }

 private:
  bool isGrid() const { return expected_ == VtkDataset::Kind::kUnstructuredGrid; }

  // --- locations and errors ---

  std::string where(const Token& t) const {
    return binary_ ? fmt::format("{}: byte {}", out_.source, t.at)
                   : fmt::format("{}:{}", out_.source, t.line);
  }
  [[noreturn]] void fail(const Token& t, const std::string& what) const {
    throw InputError(fmt::format("{}: {}", where(t), what));
  }
  Token here() const { return Token{{}, pos_, line_}; }
  [[noreturn]] void failEnd(std::string_view expected) const {
    fail(here(), fmt::format("file ends; expected {}", expected));
  }

  // --- tokens ---

  bool skipSpace() {
    while (pos_ < data_.size() && isSpace(data_[pos_])) {
      if (data_[pos_] == '\n') ++line_;
      ++pos_;
    }
    return pos_ < data_.size();
  }
  std::optional<Token> nextToken() {
    if (!skipSpace()) return std::nullopt;
    Token t{{}, pos_, line_};
    const size_t start = pos_;
    while (pos_ < data_.size() && !isSpace(data_[pos_])) ++pos_;
    t.text = data_.substr(start, pos_ - start);
    return t;
  }
  // `expected` (a text, or a function making it, called only on failure) names what is missing.
  template <class Expected>
  Token token(const Expected& expected) {
    std::optional<Token> t = nextToken();
    if (!t) failEnd(describe(expected));
    return *t;
  }
  template <class What>
  static std::string describe(const What& what) {
    if constexpr (std::is_invocable_v<What>)
      return what();
    else
      return std::string(what);
  }
  // The rest of the current line, '\r' removed; false at end of file.
  bool restOfLine(std::string_view& line) {
    if (pos_ >= data_.size()) return false;
    const size_t end = std::min(data_.find('\n', pos_), data_.size());
    line = data_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end < data_.size() ? end + 1 : end;
    if (end < data_.size()) ++line_;
    return true;
  }
  // Binary data start after the line of their section header.
  void startBinaryData(std::string_view what) {
    std::string_view ignored;
    if (!restOfLine(ignored)) failEnd(what);
  }
  template <class What>
  long long integer(const Token& t, const What& what) const {
    long long v = 0;
    if (!parseInt(t.text, v))
      fail(t, fmt::format("expected {}, got '{}'", describe(what), excerpt(t.text)));
    return v;
  }
  long long count(const Token& t, std::string_view what) const {
    const long long v = integer(t, what);
    if (v < 0) fail(t, fmt::format("expected {}, got {}", what, v));
    return v;
  }
  DataType dataType(const Token& t, bool numericOnly) const {
    const std::optional<DataType> type = dataTypeNamed(t.text);
    if (!type)
      fail(t, fmt::format("unknown data type '{}'; expected float, double, int, unsigned_char, "
                          "vtktypeint64 or another VTK type name",
                          excerpt(t.text)));
    if (numericOnly && type->kind != DataType::kNumeric)
      fail(t, fmt::format("data type '{}' here; expected a numeric type", excerpt(t.text)));
    return *type;
  }

  // Refuses `values` values of `bytesEach` bytes (binary) that the rest of the file cannot hold,
  // before anything is allocated for them; ASCII values take at least 2 bytes with a separator.
  void requireRoom(const Token& t, long long values, int bytesEach, std::string_view what) const {
    const long long left = static_cast<long long>(data_.size() - pos_);
    const long long most = binary_ ? left / bytesEach : left / 2 + 1;
    if (values <= most) return;
    // The least byte count, named only where it is a number (a count from a file may be as large
    // as a long long holds).
    const long long each = binary_ ? bytesEach : 2;
    const std::string least =
        values <= LLONG_MAX / each
            ? fmt::format("at least {} bytes", binary_ ? values * each : 2 * values - 1)
            : fmt::format("{} bytes each", each);
    fail(t, fmt::format("{} {} values ({}), but the file has only {} bytes left", what, values,
                        least, left));
  }
  // tuples x components, refused when the file cannot hold them (also before the product could
  // overflow).
  long long requireTuples(const Token& t, long long tuples, long long components, int bytesEach,
                          std::string_view what) const {
    const long long left = static_cast<long long>(data_.size() - pos_);
    if (components > 0 && tuples > left / components + 1)
      fail(t, fmt::format("{} {} x {} values, but the file has only {} bytes left", what, tuples,
                          components, left));
    requireRoom(t, tuples * components, bytesEach, what);
    return tuples * components;
  }

  // tuples x components bits, refused when the file cannot hold them: binary bits are packed 8 to
  // a byte (the count is checked before it is rounded up, so that it cannot overflow).
  long long requireBits(const Token& t, long long tuples, long long components,
                        std::string_view what) const {
    const long long left = static_cast<long long>(data_.size() - pos_);
    const long long mostBits = binary_ ? 8 * left : left / 2 + 1;
    if (tuples > mostBits / components + 1 || tuples * components > mostBits)
      fail(t, fmt::format("{} {} x {} bits, but the file has only {} bytes left", what, tuples,
                          components, left));
    return tuples * components;
  }

  // --- values ---

  // Reads `count` values of the numeric `type` (ASCII tokens or big-endian binary), calling
  // sink(index, value, where). Non-finite values are refused when `finite`.
  template <class Sink>
  void readValues(const DataType& type, long long count, std::string_view what, bool finite,
                  Sink&& sink) {
    if (count == 0) return;
    const int bytes = vtkScalarBytes(type.scalar);
    if (binary_) {
      startBinaryData(what);
      if (static_cast<long long>((data_.size() - pos_) / bytes) < count)
        failEnd(fmt::format("{} binary values of {}", count, what));
      const auto* p = reinterpret_cast<const unsigned char*>(data_.data() + pos_);
      for (long long i = 0; i < count; ++i) {
        const double v = decodeVtkScalar(p + i * bytes, type.scalar, true);
        const Token at{{}, pos_ + static_cast<size_t>(i * bytes), line_};
        if (finite && !std::isfinite(v))
          fail(at, fmt::format("value {} of {} is not a finite number", v, what));
        sink(i, v, at);
      }
      pos_ += static_cast<size_t>(count * bytes);
      return;
    }
    for (long long i = 0; i < count; ++i) {
      const Token t =
          token([&] { return fmt::format("{} values of {}, read {}", count, what, i); });
      double v = 0;
      const std::string why = parseVtkScalar(t.text, type.scalar, v);
      if (!why.empty()) fail(t, fmt::format("value '{}' of {}: {}", excerpt(t.text), what, why));
      if (finite && !std::isfinite(v))
        fail(t, fmt::format("value '{}' is not a finite number", excerpt(t.text)));
      sink(i, v, t);
    }
  }

  // Reads an array of any type (bit and string arrays included) of tuples x components values,
  // with the METADATA block that may follow; returns it when it is numeric or bit.
  VtkArray readArray(const Token& t, const DataType& type, long long tuples, long long components,
                     std::string_view what) {
    VtkArray array;
    array.tuples = tuples;
    if (components < 1 || components > INT_MAX)
      fail(t, fmt::format("{} has {} components; expected at least 1", what, components));
    array.components = static_cast<int>(components);
    if (type.kind == DataType::kString) {
      skipStrings(t, requireTuples(t, tuples, components, 1, what), what);
      array.numeric = false;
    } else if (type.kind == DataType::kBit) {
      array.values.resize(static_cast<size_t>(requireBits(t, tuples, components, what)));
      readBits(tuples * components, what, array.values);
    } else {
      const long long n = requireTuples(t, tuples, components, vtkScalarBytes(type.scalar), what);
      array.values.resize(static_cast<size_t>(n));
      readValues(type, n, what, false,
                 [&](long long i, double v, const Token&) { array.values[i] = v; });
    }
    skipMetadata(components);
    return array;
  }

  void readBits(long long count, std::string_view what, std::vector<double>& values) {
    if (count == 0) return;
    if (binary_) {
      startBinaryData(what);
      const long long bytes = (count + 7) / 8;
      if (static_cast<long long>(data_.size() - pos_) < bytes)
        failEnd(fmt::format("{} bytes of bits of {}", bytes, what));
      for (long long i = 0; i < count; ++i)
        values[i] = (static_cast<unsigned char>(data_[pos_ + i / 8]) >> (7 - i % 8)) & 1;
      pos_ += static_cast<size_t>(bytes);
      return;
    }
    readValues(DataType{DataType::kNumeric, VtkScalar::kInt64}, count, what, false,
               [&](long long i, double v, const Token&) { values[i] = v != 0; });
  }

  // String arrays: one %-encoded string per line (ASCII) or length-prefixed strings (binary).
  void skipStrings(const Token& t, long long count, std::string_view what) {
    std::string_view line;
    restOfLine(line);
    for (long long i = 0; i < count; ++i) {
      if (!binary_) {
        if (!restOfLine(line)) failEnd(fmt::format("{} strings of {}", count, what));
        continue;
      }
      if (pos_ >= data_.size()) failEnd(fmt::format("{} strings of {}", count, what));
      const auto first = static_cast<unsigned char>(data_[pos_]);
      static constexpr int kHeaderBytes[] = {8, 4, 2, 1};
      const int headerBytes = kHeaderBytes[first >> 6];
      if (data_.size() - pos_ < static_cast<size_t>(headerBytes))
        failEnd(fmt::format("the length of string {} of {}", i, what));
      unsigned long long length = 0;
      for (int k = 0; k < headerBytes; ++k)
        length = (length << 8) | static_cast<unsigned char>(data_[pos_ + k]);
      if (headerBytes < 8) length &= (1ULL << (8 * headerBytes - 2)) - 1;
      pos_ += headerBytes;
      if (length > data_.size() - pos_)
        fail(t, fmt::format("string {} of {} is {} bytes long, but the file has only {} left", i,
                            what, length, data_.size() - pos_));
      pos_ += static_cast<size_t>(length);
    }
  }

  // After an array VTK accepts a block "METADATA" ... ending at a blank line (component names,
  // information keys); nothing in it is needed here.
  void skipMetadata(long long components) {
    const size_t savedPos = pos_;
    const int savedLine = line_;
    skipSpace();
    if (data_.size() - pos_ < 8 || lower(data_.substr(pos_, 8)) != "metadata") {
      pos_ = savedPos, line_ = savedLine;
      return;
    }
    std::string_view line;
    restOfLine(line);
    while (restOfLine(line)) {
      if (trim(line).empty()) return;
      if (lower(trim(line)).rfind("component_names", 0) != 0) continue;
      long long names = 0;
      while (names < components && restOfLine(line)) ++names;
    }
  }

  // --- sections ---

  void header() {
    std::string_view line;
    restOfLine(line);
    constexpr std::string_view kPrefix = "# vtk DataFile Version";
    if (line.substr(0, kPrefix.size()) != kPrefix)
      fail(Token{{}, 0, 1}, fmt::format("expected '# vtk DataFile Version <n.m>' as the first line "
                                        "of a legacy VTK file, got '{}'",
                                        excerpt(line)));
    // As VTK, a version that cannot be read counts as 0.0 (the older cell format).
    const std::string_view version = trim(line.substr(kPrefix.size()));
    major_ = 0;
    for (size_t i = 0; i < version.size() && std::isdigit(static_cast<unsigned char>(version[i]));
         ++i)
      major_ = std::min(major_ * 10 + (version[i] - '0'), 1000);
    if (!restOfLine(line)) failEnd("a title line");
    const Token type = token("ASCII or BINARY");
    const std::string typeName = lower(type.text);
    if (typeName != "ascii" && typeName != "binary")
      fail(type, fmt::format("expected ASCII or BINARY, got '{}'", excerpt(type.text)));
    binary_ = typeName == "binary";
    const Token dataset = token("DATASET");
    if (lower(dataset.text) != "dataset")
      fail(dataset, fmt::format("expected DATASET, got '{}'", excerpt(dataset.text)));
    const Token kind = token("the dataset type");
    const std::string kindName = lower(kind.text);
    if (isGrid() && kindName != "unstructured_grid")
      throw InputError(
          fmt::format("{}: not a legacy VTK unstructured grid; expected 'DATASET "
                      "UNSTRUCTURED_GRID' with tetrahedra",
                      out_.source));
    if (!isGrid() && kindName != "polydata")
      throw InputError(
          fmt::format("{}: not a legacy VTK polydata file; expected 'DATASET "
                      "POLYDATA' with triangles",
                      out_.source));
  }

  void readPoints(const Token& keyword) {
    if (numPoints_ >= 0) fail(keyword, "a second POINTS section; expected one");
    const Token n = token("the number of points");
    const long long count = this->count(n, "the number of points");
    if (count > INT_MAX) fail(n, fmt::format("{} points; expected at most {}", count, INT_MAX));
    const Token typeToken = token("the data type of the points");
    const DataType type = dataType(typeToken, true);
    requireTuples(typeToken, count, 3, vtkScalarBytes(type.scalar),
                  fmt::format("POINTS {} needs", count));
    out_.points.resize(count, 3);
    readValues(type, 3 * count, "POINTS", true,
               [&](long long i, double v, const Token&) { out_.points(i / 3, i % 3) = v; });
    skipMetadata(3);
    numPoints_ = count;
  }

  void requirePoints(const Token& keyword) const {
    if (numPoints_ < 0)
      fail(keyword, fmt::format("{} before POINTS; expected the points first", keyword.text));
  }

  void checkPointId(const Token& at, const CellBlock& block, long long cell, double id) const {
    if (!(id >= 0 && id < numPoints_))
      fail(at, fmt::format("{} {} refers to point {}; the file has {} points{}", block.cellWord,
                           cell, id, numPoints_,
                           numPoints_ > 0 ? fmt::format(" (0 to {})", numPoints_ - 1) : ""));
  }

  void readCells(const Token& keyword, const CellBlock& block, VtkCells& cells) {
    requirePoints(keyword);
    if (major_ >= 5)
      readOffsetCells(keyword, block, cells);
    else
      readCellRows(keyword, block, cells);
    if (&block == &kGridCells) return;
    for (long long c = 0; c < cells.size(); ++c)
      if (cells.count(c) < block.minPoints)
        throw InputError(fmt::format("{}: {} {} has {} point ids; expected at least {}",
                                     c < static_cast<long long>(cells.lines.size())
                                         ? fmt::format("{}:{}", out_.source, cells.lines[c])
                                         : out_.source,
                                     block.cellWord, c, cells.count(c), block.minPoints));
  }

  // Files before version 5: "CELLS n size", then n rows "count id id ...", size values in all.
  void readCellRows(const Token& keyword, const CellBlock& block, VtkCells& cells) {
    const Token nToken = token("the number of cells");
    const long long n = count(nToken, "the number of cells");
    const Token sizeToken = token("the size of the cell list");
    const long long size = count(sizeToken, "the size of the cell list");
    if (n > INT_MAX) fail(nToken, fmt::format("{} cells; expected at most {}", n, INT_MAX));
    if (size < n)
      fail(sizeToken, fmt::format("{} {} {}: a list of {} values cannot hold {} cells and their "
                                  "point counts",
                                  keyword.text, n, size, size, n));
    requireRoom(sizeToken, size, 4, fmt::format("{} {} {} needs", keyword.text, n, size));
    cells.offsets.reserve(static_cast<size_t>(n) + 1);
    cells.connectivity.reserve(static_cast<size_t>(size - n));
    if (binary_) {
      if (size > 0) startBinaryData(keyword.text);
      readBinaryRows(block, n, size, cells);
    } else if (rowsAreLines(n)) {
      readRowLines(keyword, block, n, size, cells);
    } else {
      readRowTokens(keyword, block, n, size, cells);
    }
  }

  void readBinaryRows(const CellBlock& block, long long n, long long size, VtkCells& cells) {
    if (static_cast<long long>((data_.size() - pos_) / 4) < size)
      failEnd(fmt::format("{} binary values of the cell list", size));
    const auto* p = reinterpret_cast<const unsigned char*>(data_.data() + pos_);
    const auto value = [&](long long k) {
      return decodeVtkScalar(p + 4 * k, VtkScalar::kInt32, true);
    };
    long long k = 0;
    for (long long c = 0; c < n; ++c) {
      const Token at{{}, pos_ + static_cast<size_t>(4 * k), line_};
      if (k >= size)
        fail(at,
             fmt::format("the cell list of {} values ends before {} {}", size, block.cellWord, c));
      const double pointCount = value(k);
      if (pointCount < 1 || pointCount > size - k - 1)
        fail(at, fmt::format("{} {} has a point count of {}; expected 1 to {} (the values left in "
                             "the list)",
                             block.cellWord, c, pointCount, size - k - 1));
      for (long long i = 1; i <= pointCount; ++i) {
        const double id = value(k + i);
        checkPointId(Token{{}, at.at + static_cast<size_t>(4 * i), line_}, block, c, id);
        cells.connectivity.push_back(static_cast<int>(id));
      }
      k += 1 + static_cast<long long>(pointCount);
      cells.offsets.push_back(static_cast<long long>(cells.connectivity.size()));
    }
    if (k != size)
      fail(Token{{}, pos_ + static_cast<size_t>(4 * k), line_},
           fmt::format("the cell list announces {} values; its {} cells hold {}", size, n, k));
    pos_ += static_cast<size_t>(4 * size);
  }

  // VTK and most writers put one cell per line; when the n lines after the header hold the cells
  // (the token after them is a keyword), a row whose count disagrees with its ids is named exactly.
  bool rowsAreLines(long long n) const {
    size_t p = pos_;
    const size_t headerEnd = data_.find('\n', p);
    if (headerEnd == std::string_view::npos || !trim(data_.substr(p, headerEnd - p)).empty())
      return false;
    p = headerEnd + 1;
    for (long long c = 0; c < n; ++c) {
      const size_t end = std::min(data_.find('\n', p), data_.size());
      if (trim(data_.substr(p, end - p)).empty()) return false;
      if (end == data_.size()) return c == n - 1;
      p = end + 1;
    }
    while (p < data_.size() && isSpace(data_[p])) ++p;
    return p == data_.size() || std::isalpha(static_cast<unsigned char>(data_[p]));
  }

  void readRowLines(const Token& keyword, const CellBlock& block, long long n, long long size,
                    VtkCells& cells) {
    std::string_view line;
    restOfLine(line);  // the rest of the header line, blank
    long long total = 0;
    for (long long c = 0; c < n; ++c) {
      const Token rowStart = here();
      restOfLine(line);
      const std::vector<std::string_view> fields = splitBlanks(line);
      const Token countToken{fields[0], rowStart.at, rowStart.line};
      const long long pointCount = integer(
          countToken, [&] { return fmt::format("the point count of {} {}", block.cellWord, c); });
      const long long ids = static_cast<long long>(fields.size()) - 1;
      if (pointCount != ids)
        fail(countToken, fmt::format("{} {} has {} point ids but its count says {}", block.cellWord,
                                     c, ids, pointCount));
      for (long long i = 1; i <= ids; ++i) {
        const Token idToken{fields[i], rowStart.at, rowStart.line};
        const long long id =
            integer(idToken, [&] { return fmt::format("a point id of {} {}", block.cellWord, c); });
        checkPointId(idToken, block, c, static_cast<double>(id));
        cells.connectivity.push_back(static_cast<int>(id));
      }
      total += 1 + ids;
      cells.offsets.push_back(static_cast<long long>(cells.connectivity.size()));
      cells.lines.push_back(rowStart.line);
    }
    if (total != size)
      fail(keyword, fmt::format("{} {} {} announces {} values; its {} rows hold {}", keyword.text,
                                n, size, size, n, total));
  }

  // Rows not one per line are read as a stream of values; a keyword met where a value should be
  // means a count before it announced more ids than its row has.
  void readRowTokens(const Token& keyword, const CellBlock& block, long long n, long long size,
                     VtkCells& cells) {
    const auto endsEarly = [&](const Token& t, const std::string& where) {
      if (!t.text.empty() && std::isalpha(static_cast<unsigned char>(t.text[0])))
        fail(t, fmt::format("the {} rows end {} (got '{}'); a point count among them announces "
                            "more ids than its row has",
                            keyword.text, where, excerpt(t.text)));
    };
    long long k = 0;
    for (long long c = 0; c < n; ++c) {
      const Token countToken = token(
          [&] { return fmt::format("the point count of {} {} of {}", block.cellWord, c, n); });
      endsEarly(countToken, fmt::format("after {} of their {} cells", c, n));
      const long long left = size - k - 1;
      const long long pointCount = integer(
          countToken, [&] { return fmt::format("the point count of {} {}", block.cellWord, c); });
      if (pointCount < 1 || pointCount > left)
        fail(
            countToken,
            fmt::format("{} {} has a point count of {}; expected 1 to {} (the values left in "
                        "{} {} {})",
                        block.cellWord, c, pointCount, std::max(left, 0LL), keyword.text, n, size));
      for (long long i = 0; i < pointCount; ++i) {
        const Token idToken =
            token([&] { return fmt::format("point id {} of {} {}", i, block.cellWord, c); });
        endsEarly(idToken, fmt::format("inside {} {}", block.cellWord, c));
        const long long id =
            integer(idToken, [&] { return fmt::format("a point id of {} {}", block.cellWord, c); });
        checkPointId(idToken, block, c, static_cast<double>(id));
        cells.connectivity.push_back(static_cast<int>(id));
      }
      k += 1 + pointCount;
      cells.offsets.push_back(static_cast<long long>(cells.connectivity.size()));
      cells.lines.push_back(countToken.line);
    }
    if (k != size)
      fail(keyword, fmt::format("{} {} {} announces {} values; its {} rows hold {}", keyword.text,
                                n, size, size, n, k));
  }

  // Files of version 5: "CELLS nOffsets nConnectivity", then OFFSETS and CONNECTIVITY arrays.
  void readOffsetCells(const Token& keyword, const CellBlock& block, VtkCells& cells) {
    const Token nToken = token("the number of offsets");
    const long long numOffsets = count(nToken, "the number of offsets");
    const Token connToken = token("the size of the connectivity");
    const long long numIds = count(connToken, "the size of the connectivity");
    if (numOffsets < 1) {
      if (numIds != 0)
        fail(connToken, fmt::format("{} point ids with no offsets; expected 0", numIds));
      return;  // no cells; VTK reads no OFFSETS then
    }
    if (numOffsets - 1 > INT_MAX)
      fail(nToken, fmt::format("{} cells; expected at most {}", numOffsets - 1, INT_MAX));
    const std::string needs = fmt::format("{} {} {} needs", keyword.text, numOffsets, numIds);
    requireRoom(nToken, numOffsets, 1, needs);
    requireRoom(connToken, numIds, 1, needs);
    requireRoom(connToken, numOffsets + numIds, 1, needs);

    const Token offsetsKeyword = token("OFFSETS");
    if (lower(offsetsKeyword.text) != "offsets")
      fail(offsetsKeyword, fmt::format("expected OFFSETS after {} in a version {} file, got '{}'",
                                       keyword.text, major_, excerpt(offsetsKeyword.text)));
    const DataType offsetType = integerType(token("the data type of the offsets"));
    requireRoom(offsetsKeyword, numOffsets, vtkScalarBytes(offsetType.scalar), "OFFSETS needs");
    cells.offsets.resize(static_cast<size_t>(numOffsets));
    readValues(
        offsetType, numOffsets, "OFFSETS", false, [&](long long i, double v, const Token& at) {
          const double previous = i == 0 ? 0.0 : static_cast<double>(cells.offsets[i - 1]);
          if (i == 0 && v != 0) fail(at, fmt::format("the first offset is {}; expected 0", v));
          if (v < previous || v > static_cast<double>(numIds))
            fail(at, fmt::format("offset {} is {}; expected a value from {} to {} (offsets never "
                                 "decrease and end at the connectivity size)",
                                 i, v, previous, numIds));
          if (i == numOffsets - 1 && v != static_cast<double>(numIds))
            fail(at, fmt::format("the last offset is {}; expected the connectivity size {}", v,
                                 numIds));
          cells.offsets[i] = static_cast<long long>(v);
        });
    skipMetadata(1);

    const Token connKeyword = token("CONNECTIVITY");
    if (lower(connKeyword.text) != "connectivity")
      fail(connKeyword, fmt::format("expected CONNECTIVITY after the offsets, got '{}'",
                                    excerpt(connKeyword.text)));
    const DataType idType = integerType(token("the data type of the connectivity"));
    requireRoom(connKeyword, numIds, vtkScalarBytes(idType.scalar), "CONNECTIVITY needs");
    cells.connectivity.resize(static_cast<size_t>(numIds));
    long long cell = 0;
    readValues(idType, numIds, "CONNECTIVITY", false, [&](long long i, double v, const Token& at) {
      while (cell < numOffsets - 1 && cells.offsets[cell + 1] <= i) ++cell;
      if (!binary_)
        while (static_cast<long long>(cells.lines.size()) <= cell) cells.lines.push_back(at.line);
      checkPointId(at, block, cell, v);
      cells.connectivity[i] = static_cast<int>(v);
    });
    if (!binary_)
      while (static_cast<long long>(cells.lines.size()) < numOffsets - 1)
        cells.lines.push_back(line_);
    skipMetadata(1);
  }

  DataType integerType(const Token& t) const {
    const DataType type = dataType(t, true);
    if (!vtkScalarIsInteger(type.scalar))
      fail(t, fmt::format("data type '{}' for cell offsets or ids; expected an integer type",
                          excerpt(t.text)));
    return type;
  }

  void readCellTypes(std::vector<unsigned char>& types) {
    const Token nToken = token("the number of cell types");
    const long long n = count(nToken, "the number of cell types");
    requireRoom(nToken, n, 4, fmt::format("CELL_TYPES {} needs", n));
    types.resize(static_cast<size_t>(n));
    readValues(DataType{DataType::kNumeric, VtkScalar::kInt32}, n, "CELL_TYPES", false,
               [&](long long i, double v, const Token& at) {
                 const VtkCellType* type = findVtkCellType(static_cast<long long>(v));
                 if (!type) fail(at, fmt::format("cell {} has the unknown VTK cell type {}", i, v));
                 types[i] = static_cast<unsigned char>(type->id);
               });
  }

  void finishGridCells(const std::optional<Token>& typesToken, std::vector<unsigned char>& types) {
    VtkCells& cells = out_.cells;
    if (!typesToken) {
      if (haveCells_ && cells.size() > 0)
        throw InputError(fmt::format("{}: CELLS without CELL_TYPES; expected the type of each cell",
                                     out_.source));
      return;
    }
    if (static_cast<long long>(types.size()) != cells.size())
      fail(*typesToken, fmt::format("CELL_TYPES lists {} types; expected one per cell ({} in "
                                    "CELLS)",
                                    types.size(), cells.size()));
    cells.types = std::move(types);
    for (long long c = 0; c < cells.size(); ++c) {
      const VtkCellType& type = *findVtkCellType(cells.types[c]);
      const std::string expected = vtkCellCountExpectation(type, cells.count(c));
      if (!expected.empty())
        throw InputError(fmt::format("{}: cell {} ({}) has {} point ids; expected {}",
                                     out_.cellLocation(c), c, describeVtkCellType(type),
                                     cells.count(c), expected));
    }
  }

  const CellBlock* polyBlockNamed(const std::string& keyword) const {
    if (isGrid()) return nullptr;
    for (const CellBlock& block : kPolyBlocks)
      if (keyword == lower(block.keyword)) return &block;
    return nullptr;
  }
  VtkCells& polyCells(const CellBlock& block) {
    VtkCells* blocks[] = {&out_.verts, &out_.lines, &out_.polys, &out_.strips};
    return *blocks[&block - kPolyBlocks];
  }

  // --- attribute data ---

  // Which of VTK's attribute slots an array fills; VTK keeps only the first array of each slot.
  enum Slot {
    kScalars,
    kVectors,
    kNormals,
    kTensors,
    kTCoords,
    kGlobalIds,
    kPedigreeIds,
    kEdgeFlags,
    kNumSlots
  };

  void readAttributes(const Token& first) {
    Token section = first;
    long long n = sectionSize(section);
    bool filled[2][kNumSlots] = {};
    while (std::optional<Token> t = nextToken()) {
      const std::string keyword = lower(t->text);
      const bool cellData = lower(section.text) == "cell_data";
      bool* slots = filled[cellData ? 1 : 0];
      const auto keep = [&](VtkArray array, Slot slot) {
        const bool slotFree = !slots[slot];
        slots[slot] = true;
        if (cellData && slotFree && array.numeric) addCellArray(std::move(array));
      };
      if (keyword == "cell_data" || keyword == "point_data") {
        section = *t;
        n = sectionSize(section);
      } else if (keyword == "scalars") {
        const std::string name = decodeName(token("the name of the scalars").text);
        const Token typeToken = token("the data type of the scalars");
        const DataType type = dataType(typeToken, false);
        Token next = token("LOOKUP_TABLE");
        long long components = 1;
        if (lower(next.text) != "lookup_table") {
          components = integer(next, "the number of components or LOOKUP_TABLE");
          if (components < 1)
            fail(next, fmt::format("scalars '{}' have {} components; expected at least 1",
                                   excerpt(name), components));
          next = token("LOOKUP_TABLE");
        }
        if (lower(next.text) != "lookup_table")
          fail(next, fmt::format("expected LOOKUP_TABLE after the scalars header, got '{}'",
                                 excerpt(next.text)));
        token("the lookup table name");
        VtkArray array =
            readArray(typeToken, type, n, components, fmt::format("SCALARS {}", excerpt(name)));
        array.name = name;
        keep(std::move(array), kScalars);
      } else if (keyword == "color_scalars") {
        const std::string name = decodeName(token("the name of the color scalars").text);
        const Token nv = token("the number of color components");
        const long long components = count(nv, "the number of color components");
        const DataType type{DataType::kNumeric, binary_ ? VtkScalar::kUInt8 : VtkScalar::kFloat32};
        VtkArray array =
            readArray(nv, type, n, components, fmt::format("COLOR_SCALARS {}", excerpt(name)));
        array.name = name;
        keep(std::move(array), kScalars);
      } else if (keyword == "lookup_table") {
        token("the lookup table name");
        const Token sizeToken = token("the lookup table size");
        const long long size = count(sizeToken, "the lookup table size");
        const DataType type{DataType::kNumeric, binary_ ? VtkScalar::kUInt8 : VtkScalar::kFloat32};
        const long long values = requireTuples(sizeToken, size, 4, 1, "LOOKUP_TABLE needs");
        if (values > 0 && binary_) startBinaryData("the lookup table");
        if (binary_) {
          if (static_cast<long long>(data_.size() - pos_) < values) failEnd("the lookup table");
          pos_ += static_cast<size_t>(values);
        } else {
          readValues(type, values, "LOOKUP_TABLE", false, [](long long, double, const Token&) {});
        }
      } else if (keyword == "vectors" || keyword == "normals" || keyword == "tensors" ||
                 keyword == "tensors6" || keyword == "global_ids" || keyword == "pedigree_ids" ||
                 keyword == "edge_flags" || keyword == "texture_coordinates") {
        const std::string name = decodeName(token("the name of the attribute").text);
        long long components = keyword == "tensors" ? 9 : keyword == "tensors6" ? 6 : 1;
        if (keyword == "vectors" || keyword == "normals") components = 3;
        if (keyword == "texture_coordinates") {
          const Token dim = token("the texture dimension");
          components = integer(dim, "the texture dimension");
          if (components < 1 || components > 3)
            fail(dim, fmt::format("texture dimension {}; expected 1, 2 or 3", components));
        }
        const Token typeToken = token("the data type of the attribute");
        const DataType type = dataType(typeToken, false);
        VtkArray array =
            readArray(typeToken, type, n, components, fmt::format("{} {}", t->text, excerpt(name)));
        array.name = name;
        const Slot slot = keyword == "vectors"               ? kVectors
                          : keyword == "normals"             ? kNormals
                          : keyword == "global_ids"          ? kGlobalIds
                          : keyword == "pedigree_ids"        ? kPedigreeIds
                          : keyword == "edge_flags"          ? kEdgeFlags
                          : keyword == "texture_coordinates" ? kTCoords
                                                             : kTensors;
        keep(std::move(array), slot);
      } else if (keyword == "field") {
        readField(cellData);
      } else {
        fail(*t, fmt::format("unknown keyword '{}' in {}; expected SCALARS, VECTORS, NORMALS, "
                             "TENSORS, TEXTURE_COORDINATES, COLOR_SCALARS, LOOKUP_TABLE, FIELD, "
                             "CELL_DATA or POINT_DATA",
                             excerpt(t->text), section.text));
      }
    }
  }

  long long sectionSize(const Token& section) {
    const Token nToken = token(fmt::format("the size of {}", section.text));
    const long long n = count(nToken, fmt::format("the size of {}", section.text));
    const bool cellData = lower(section.text) == "cell_data";
    const long long expected = cellData ? out_.numCells() : std::max(numPoints_, 0LL);
    if (n != expected)
      fail(nToken, fmt::format("{} {}; expected the number of {} ({})", section.text, n,
                               cellData ? "cells" : "points", expected));
    return n;
  }

  // "FIELD name numArrays", then per array "name components tuples type" and its values; the
  // arrays are kept when they are cell data.
  void readField(bool keep) {
    token("the name of the field");
    const Token nToken = token("the number of arrays");
    const long long numArrays = count(nToken, "the number of arrays");
    requireRoom(nToken, numArrays, 1, "FIELD needs at least");
    for (long long a = 0; a < numArrays; ++a) {
      const Token nameToken =
          token([&] { return fmt::format("array {} of {} in FIELD", a, numArrays); });
      if (nameToken.text == "NULL_ARRAY") continue;
      const std::string name = decodeName(nameToken.text);
      const Token componentsToken = token("the number of components");
      const long long components = count(componentsToken, "the number of components");
      const Token tuplesToken = token("the number of tuples");
      const long long tuples = count(tuplesToken, "the number of tuples");
      const Token typeToken = token("the data type of the array");
      const DataType type = dataType(typeToken, false);
      VtkArray array = readArray(typeToken, type, tuples, components,
                                 fmt::format("FIELD array {}", excerpt(name)));
      array.name = name;
      if (keep && array.numeric) addCellArray(std::move(array));
    }
  }

  // As vtkFieldData::AddArray: an array replaces the one of the same name.
  void addCellArray(VtkArray array) {
    for (VtkArray& existing : out_.cellArrays)
      if (existing.name == array.name) {
        existing = std::move(array);
        return;
      }
    out_.cellArrays.push_back(std::move(array));
  }

  const std::string_view data_;
  const VtkDataset::Kind expected_;
  size_t pos_ = 0;
  int line_ = 1;
  bool binary_ = false;
  int major_ = 0;
  long long numPoints_ = -1;
  bool haveCells_ = false;
  VtkDataset out_;
};

}  // namespace

VtkDataset readLegacyVtk(const std::string& path, VtkDataset::Kind expected) {
  const MappedFile file(path);
  return LegacyParser(file.bytes(), path, expected).parse();
}

}  // namespace bcassim::io
