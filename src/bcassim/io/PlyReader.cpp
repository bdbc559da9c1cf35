#include "bcassim/io/PlyReader.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"
#include "bcassim/io/TextTokens.h"

namespace bcassim::io {
namespace {

enum class Format { Ascii, LittleEndian, BigEndian };
enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

constexpr const char* kTypeList =
    "char, uchar, short, ushort, int, uint, float, double (or int8, uint8, int16, uint16, int32, "
    "uint32, float32, float64)";

std::optional<Scalar> scalarType(std::string_view name) {
  struct Named {
    std::string_view a, b;
    Scalar type;
  };
  constexpr Named kTypes[] = {
      {"char", "int8", Scalar::Int8},        {"uchar", "uint8", Scalar::UInt8},
      {"short", "int16", Scalar::Int16},     {"ushort", "uint16", Scalar::UInt16},
      {"int", "int32", Scalar::Int32},       {"uint", "uint32", Scalar::UInt32},
      {"float", "float32", Scalar::Float32}, {"double", "float64", Scalar::Float64}};
  for (const Named& t : kTypes)
    if (name == t.a || name == t.b) return t.type;
  return std::nullopt;
}

int sizeOf(Scalar t) {
  switch (t) {
    case Scalar::Int8:
    case Scalar::UInt8:
      return 1;
    case Scalar::Int16:
    case Scalar::UInt16:
      return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32:
      return 4;
    case Scalar::Float64:
      return 8;
  }
  return 8;
}

bool isFloat(Scalar t) { return t == Scalar::Float32 || t == Scalar::Float64; }

struct Property {
  std::string name;
  bool list = false;
  Scalar count = Scalar::UInt8;   // a list's length type
  Scalar type = Scalar::Float32;  // the value's (a list's items')
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;
};

// Where a value is read, for messages: "vertex 3: property 'y'".
struct Where {
  const Element* element = nullptr;
  long long index = 0;
  const Property* property = nullptr;
  std::string describe() const {
    return fmt::format("{} {}: property '{}'", excerpt(element->name), index,
                       excerpt(property->name));
  }
};

// The data after the header, value by value: blank-separated numbers (ASCII, their line counted)
// or packed binary values of either byte order.
class DataCursor {
 public:
  DataCursor(std::string_view data, Format format, int line, const std::string& path)
      : data_(data), format_(format), text_(data, line, false), path_(path) {}

  double read(Scalar type, const Where& where) {
    return format_ == Format::Ascii ? readText(type, where) : readBinary(type, where);
  }

  // Skips `count` values of `type` (a list nobody reads).
  void skip(long long count, Scalar type, const Where& where) {
    if (format_ != Format::Ascii) {
      const auto size = static_cast<unsigned long long>(sizeOf(type));
      if (static_cast<unsigned long long>(count) > (data_.size() - pos_) / size) endOfData(where);
      pos_ += static_cast<size_t>(count) * size;
      return;
    }
    for (long long k = 0; k < count; ++k) readText(type, where);
  }

  // Throws if anything but blanks (ASCII) or nothing at all (binary) is left.
  void requireEnd(const std::string& lastElement) {
    if (format_ == Format::Ascii) {
      const std::string_view extra = text_.next();
      if (!extra.empty())
        throw InputError(
            fmt::format("{}:{}: '{}' after the last element ({}); expected the file to end there",
                        path_, text_.line(), excerpt(extra), excerpt(lastElement)));
      return;
    }
    if (pos_ < data_.size())
      throw InputError(
          fmt::format("{}: {} bytes after the last element ({}); expected the file to end there",
                      path_, data_.size() - pos_, excerpt(lastElement)));
  }

 private:
  [[noreturn]] void endOfData(const Where& where) const {
    throw InputError(fmt::format(
        "{}: the file ends at {}; expected {} {} element{}", path_, where.describe(),
        where.element->count, excerpt(where.element->name), where.element->count == 1 ? "" : "s"));
  }

  double readText(Scalar type, const Where& where) {
    const std::string_view field = text_.next();
    if (field.empty()) endOfData(where);
    if (isFloat(type)) {
      double v = 0.0;
      if (!parseDouble(field, v))
        throw InputError(fmt::format("{}:{}: {} is '{}'; expected a number", path_, text_.line(),
                                     where.describe(), excerpt(field)));
      return v;
    }
    long long v = 0;
    if (!parseInt(field, v))
      throw InputError(fmt::format("{}:{}: {} is '{}'; expected an integer", path_, text_.line(),
                                   where.describe(), excerpt(field)));
    return static_cast<double>(v);
  }

  double readBinary(Scalar type, const Where& where) {
    const int size = sizeOf(type);
    if (data_.size() - pos_ < static_cast<size_t>(size)) endOfData(where);
    std::uint64_t word = 0;
    for (int k = 0; k < size; ++k) {
      const auto byte = static_cast<unsigned char>(data_[pos_ + static_cast<size_t>(k)]);
      if (format_ == Format::BigEndian)
        word = (word << 8) | byte;
      else
        word |= static_cast<std::uint64_t>(byte) << (8 * k);
    }
    pos_ += static_cast<size_t>(size);
    switch (type) {
      case Scalar::Int8:
        return static_cast<std::int8_t>(word);
      case Scalar::UInt8:
        return static_cast<std::uint8_t>(word);
      case Scalar::Int16:
        return static_cast<std::int16_t>(word);
      case Scalar::UInt16:
        return static_cast<std::uint16_t>(word);
      case Scalar::Int32:
        return static_cast<std::int32_t>(word);
      case Scalar::UInt32:
        return static_cast<std::uint32_t>(word);
      case Scalar::Float32:
        return std::bit_cast<float>(static_cast<std::uint32_t>(word));
      case Scalar::Float64:
        return std::bit_cast<double>(word);
    }
    return 0.0;
  }

  std::string_view data_;
  Format format_;
  size_t pos_ = 0;   // binary
  TextTokens text_;  // ASCII
  const std::string& path_;
};

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  size_t dataOffset = 0;
  int dataLine = 0;  // the line the data starts on (ASCII)
};

Header parseHeader(std::string_view bytes, const std::string& path) {
  Header h;
  size_t pos = 0;
  int number = 0;
  bool formatSeen = false;
  const auto fail = [&](const std::string& what) -> void {
    throw InputError(fmt::format("{}:{}: {}", path, number, what));
  };
  for (;;) {
    if (pos >= bytes.size())
      throw InputError(
          fmt::format("{}: no 'end_header' line; expected the PLY header to end with one", path));
    size_t end = bytes.find('\n', pos);
    const bool last = end == std::string_view::npos;
    std::string_view line = bytes.substr(pos, last ? std::string_view::npos : end - pos);
    pos = last ? bytes.size() : end + 1;
    ++number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::vector<std::string_view> words = splitBlanks(line);
    if (number == 1) {
      if (words.size() != 1 || words[0] != "ply")
        fail(fmt::format("'{}'; expected 'ply' (a PLY file's first line)", excerpt(line)));
      continue;
    }
    if (words.empty()) continue;
    const std::string_view key = words[0];
    if (key == "comment" || key == "obj_info") continue;
    if (!formatSeen) {
      if (key != "format" || words.size() != 3 || words[2] != "1.0" ||
          (words[1] != "ascii" && words[1] != "binary_little_endian" &&
           words[1] != "binary_big_endian"))
        fail(
            fmt::format("'{}'; expected 'format ascii 1.0', 'format binary_little_endian "
                        "1.0' or 'format binary_big_endian 1.0'",
                        excerpt(line)));
      h.format = words[1] == "ascii"                  ? Format::Ascii
                 : words[1] == "binary_little_endian" ? Format::LittleEndian
                                                      : Format::BigEndian;
      formatSeen = true;
    } else if (key == "element") {
      long long count = 0;
      if (words.size() != 3 || !parseInt(words[2], count) || count < 0 ||
          count > std::numeric_limits<int>::max())
        fail(fmt::format("'{}'; expected 'element NAME COUNT' with a count in [0, 2^31)",
                         excerpt(line)));
      for (const Element& e : h.elements)
        if (e.name == words[1]) fail(fmt::format("element '{}' declared twice", excerpt(words[1])));
      h.elements.push_back({std::string(words[1]), count, {}});
    } else if (key == "property") {
      if (h.elements.empty()) fail("a property before any element; expected 'element' first");
      Property p;
      const bool list = words.size() == 5 && words[1] == "list";
      if (!list && words.size() != 3)
        fail(
            fmt::format("'{}'; expected 'property TYPE NAME' or 'property list COUNT_TYPE "
                        "TYPE NAME'",
                        excerpt(line)));
      for (size_t k = list ? 2 : 1; k + 1 < words.size(); ++k)
        if (!scalarType(words[k]))
          fail(
              fmt::format("property type '{}' unknown; expected {}", excerpt(words[k]), kTypeList));
      p.list = list;
      if (list) {
        p.count = *scalarType(words[2]);
        if (isFloat(p.count))
          fail(fmt::format("list length type '{}'; expected an integer type", excerpt(words[2])));
      }
      p.type = *scalarType(words[words.size() - 2]);
      p.name = std::string(words.back());
      for (const Property& q : h.elements.back().properties)
        if (q.name == p.name) fail(fmt::format("property '{}' declared twice", excerpt(p.name)));
      h.elements.back().properties.push_back(p);
    } else if (key == "end_header") {
      if (words.size() != 1) fail(fmt::format("'{}'; expected 'end_header'", excerpt(line)));
      h.dataOffset = pos;
      h.dataLine = number + 1;
      return h;
    } else {
      fail(
          fmt::format("'{}'; expected a header line (format, element, property, comment, "
                      "obj_info or end_header)",
                      excerpt(line)));
    }
  }
}

}  // namespace

PlyContents readPly(const std::string& path) {
  requireReadableFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open file", path));
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const Header header = parseHeader(bytes, path);

  const Element* vertex = nullptr;
  int axis[3] = {-1, -1, -1};
  for (const Element& e : header.elements) {
    if (e.name != "vertex") continue;
    vertex = &e;
    for (size_t k = 0; k < e.properties.size(); ++k)
      for (int a = 0; a < 3; ++a)
        if (e.properties[k].name == std::string(1, "xyz"[a])) {
          if (e.properties[k].list)
            throw InputError(fmt::format("{}: vertex property '{}' is a list; expected a number",
                                         path, "xyz"[a]));
          axis[a] = static_cast<int>(k);
        }
  }
  if (!vertex || axis[0] < 0 || axis[1] < 0 || axis[2] < 0)
    throw InputError(fmt::format(
        "{}: no 'vertex' element with properties x, y and z; expected the points there", path));

  DataCursor data(std::string_view(bytes).substr(header.dataOffset), header.format, header.dataLine,
                  path);
  std::vector<double> xyz;
  std::vector<int> triangles;
  std::vector<long long> polygon;
  for (const Element& e : header.elements) {
    if (e.properties.empty()) continue;  // no data, however many (a bounded loop either way)
    const bool isVertex = &e == vertex, isFace = e.name == "face";
    Where where{&e, 0, nullptr};
    for (long long i = 0; i < e.count; ++i) {
      where.index = i;
      double point[3] = {0, 0, 0};
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        where.property = &p;
        if (!p.list) {
          const double v = data.read(p.type, where);
          for (int a = 0; a < 3; ++a)
            if (isVertex && axis[a] == static_cast<int>(k)) point[a] = v;
          continue;
        }
        const double count = data.read(p.count, where);
        if (!(count >= 0) || count > std::numeric_limits<int>::max())
          throw InputError(fmt::format("{}: {}: list of {} values; expected a length in [0, 2^31)",
                                       path, where.describe(), count));
        const auto n = static_cast<long long>(count);
        if (!isFace || (p.name != "vertex_indices" && p.name != "vertex_index")) {
          data.skip(n, p.type, where);
          continue;
        }
        if (isFloat(p.type))
          throw InputError(fmt::format("{}: {} is a list of {}s; expected integer vertex indices",
                                       path, where.describe(),
                                       p.type == Scalar::Float32 ? "float" : "double"));
        if (n < 3)
          throw InputError(
              fmt::format("{}: face {} has {} vertices; expected at least 3", path, i, n));
        polygon.clear();
        for (long long m = 0; m < n; ++m)
          polygon.push_back(static_cast<long long>(data.read(p.type, where)));
        for (long long m = 1; m + 1 < n; ++m) {
          for (const long long id :
               {polygon[0], polygon[static_cast<size_t>(m)], polygon[static_cast<size_t>(m) + 1]}) {
            if (id < 0 || id >= vertex->count)
              throw InputError(fmt::format(
                  "{}: face {} names vertex {}; expected an index in [0, {}) (the vertex count)",
                  path, i, id, vertex->count));
            triangles.push_back(static_cast<int>(id));
          }
        }
      }
      if (isVertex) xyz.insert(xyz.end(), point, point + 3);
    }
  }
  data.requireEnd(header.elements.back().name);

  PlyContents out;
  out.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
  out.F = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      triangles.data(), static_cast<Eigen::Index>(triangles.size() / 3), 3);
  return out;
}

}  // namespace bcassim::io
