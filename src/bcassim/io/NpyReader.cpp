#include "bcassim/io/NpyReader.h"

#include <fmt/format.h>

#include <bit>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string_view>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {
namespace {

enum class Kind { Float, Signed, Unsigned, Bool };
struct Dtype {
  Kind kind;
  int bytes;
  bool bigEndian;
};
constexpr const char* kDtypeList =
    "a float (f4, f8), integer (i1, i2, i4, i8, u1, u2, u4, u8) or bool (b1) dtype, little- or "
    "big-endian (e.g. <f8, >i4, |u1)";

// A plain dtype string such as '<f8', '>i4' or '|b1' (NumPy writes '|' for one-byte types).
std::optional<Dtype> parseDtype(std::string_view descr) {
  if (descr.size() != 3 || descr[2] < '1' || descr[2] > '8') return std::nullopt;
  const char order = descr[0], code = descr[1];
  const int bytes = descr[2] - '0';
  const bool power = bytes == 1 || bytes == 2 || bytes == 4 || bytes == 8;
  Dtype d{Kind::Float, bytes, order == '>'};
  switch (code) {
    case 'f':
      if (bytes != 4 && bytes != 8) return std::nullopt;
      break;
    case 'i':
      d.kind = Kind::Signed;
      if (!power) return std::nullopt;
      break;
    case 'u':
      d.kind = Kind::Unsigned;
      if (!power) return std::nullopt;
      break;
    case 'b':
      d.kind = Kind::Bool;
      if (bytes != 1) return std::nullopt;
      break;
    default:
      return std::nullopt;
  }
  const bool ordered = order == '<' || order == '>';
  if (bytes == 1 ? !(ordered || order == '|') : !ordered) return std::nullopt;
  return d;
}

// Fortran order (the first index fastest, as np.save writes a transposed array) into C order.
template <typename T>
void fortranToC(const std::vector<std::int64_t>& shape, std::vector<T>& values) {
  if (shape.size() < 2 || values.empty()) return;
  std::vector<T> c(values.size());
  std::vector<std::int64_t> index(shape.size(), 0), stride(shape.size(), 1);
  for (size_t k = 1; k < shape.size(); ++k) stride[k] = stride[k - 1] * shape[k - 1];
  std::int64_t f = 0;  // the Fortran position of C element `flat`
  for (size_t flat = 0; flat < c.size(); ++flat) {
    c[flat] = values[static_cast<size_t>(f)];
    for (size_t k = shape.size(); k-- > 0;) {  // the next C multi-index, last axis fastest
      if (++index[k] < shape[k]) {
        f += stride[k];
        break;
      }
      f -= (shape[k] - 1) * stride[k];
      index[k] = 0;
    }
  }
  values.swap(c);
}

// The header: a Python dict literal such as
// {'descr': '<f8', 'fortran_order': False, 'shape': (500, 3), }
struct Header {
  std::optional<std::string> descr;
  std::optional<bool> fortranOrder;
  std::optional<std::vector<std::int64_t>> shape;
};

class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  Header parse() {
    Header h;
    expect('{');
    while (!accept('}')) {
      const std::string key = string();
      expect(':');
      if (key == "descr") {
        skipBlanks();
        if (pos_ < text_.size() && text_[pos_] == '[')
          fail("structured dtype (a list of fields); expected a plain dtype such as '<f8'");
        h.descr = string();
      } else if (key == "fortran_order") {
        h.fortranOrder = boolean();
      } else if (key == "shape") {
        h.shape = tuple();
      } else {
        fail(fmt::format("unknown key '{}'; expected only 'descr', 'fortran_order' and 'shape'",
                         io::excerpt(key)));
      }
      if (!accept(',')) {
        expect('}');
        break;
      }
    }
    return h;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}: malformed .npy header: {}", path_, what));
  }
  void skipBlanks() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skipBlanks();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!accept(c))
      fail(fmt::format("expected '{}' at character {} of '{}'", c, pos_, io::excerpt(text_)));
  }
  std::string string() {
    skipBlanks();
    if (pos_ >= text_.size() || (text_[pos_] != '\'' && text_[pos_] != '"'))
      fail(fmt::format("expected a quoted string at character {} of '{}'", pos_,
                       io::excerpt(text_)));
    const char quote = text_[pos_++];
    const size_t end = text_.find(quote, pos_);
    if (end == std::string_view::npos) fail("unterminated string");
    std::string s(text_.substr(pos_, end - pos_));
    pos_ = end + 1;
    return s;
  }
  bool boolean() {
    skipBlanks();
    for (const auto& [word, value] : {std::pair{"True", true}, std::pair{"False", false}})
      if (text_.substr(pos_, std::strlen(word)) == word) {
        pos_ += std::strlen(word);
        return value;
      }
    fail("expected True or False for 'fortran_order'");
  }
  std::vector<std::int64_t> tuple() {
    skipBlanks();
    const size_t open = pos_;
    expect('(');
    std::vector<std::int64_t> dims;
    while (!accept(')')) {
      skipBlanks();
      const size_t start = pos_;
      while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) ++pos_;
      long long d = 0;
      if (!io::parseInt(text_.substr(start, pos_ - start), d)) {
        const size_t close = text_.find(')', open);
        fail(fmt::format("'shape' is '{}'; expected a tuple of non-negative integers",
                         io::excerpt(text_.substr(
                             open, close == std::string_view::npos ? close : close + 1 - open))));
      }
      dims.push_back(d);
      if (!accept(',')) {
        expect(')');
        break;
      }
    }
    return dims;
  }

  std::string_view text_;
  const std::string& path_;
  size_t pos_ = 0;
};

std::uint64_t littleEndian(const unsigned char* bytes, int count) {
  std::uint64_t v = 0;
  for (int k = count - 1; k >= 0; --k) v = (v << 8) | bytes[k];
  return v;
}

std::uint64_t bigEndian(const unsigned char* bytes, int count) {
  std::uint64_t v = 0;
  for (int k = 0; k < count; ++k) v = (v << 8) | bytes[k];
  return v;
}

}  // namespace

std::string formatNpyShape(const std::vector<std::int64_t>& shape) {
  std::string s = "(";
  for (size_t k = 0; k < shape.size(); ++k) s += fmt::format("{}{}", k ? ", " : "", shape[k]);
  return s + (shape.size() == 1 ? ",)" : ")");
}

std::string formatNpyIndex(const std::vector<std::int64_t>& shape, std::int64_t flat) {
  std::vector<std::int64_t> index(shape.size());
  for (size_t k = shape.size(); k-- > 0;) {
    index[k] = shape[k] > 0 ? flat % shape[k] : 0;
    flat = shape[k] > 0 ? flat / shape[k] : 0;
  }
  return formatNpyShape(index);
}

NpyArray readNpy(const std::string& path) {
  io::requireReadableFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open file", path));
  std::error_code ec;
  const std::uintmax_t fileSize = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(fmt::format("{}: cannot read the file size ({})", path, ec.message()));

  constexpr char kMagic[] = "\x93NUMPY";
  unsigned char prefix[12] = {};
  const std::uintmax_t prefixRead = std::min<std::uintmax_t>(fileSize, sizeof prefix);
  in.read(reinterpret_cast<char*>(prefix), static_cast<std::streamsize>(prefixRead));
  if (prefixRead < 8 || std::memcmp(prefix, kMagic, 6) != 0)
    throw InputError(
        fmt::format("{}: not a .npy file; expected it to start with the magic "
                    "string \\x93NUMPY",
                    path));
  const int major = prefix[6], minor = prefix[7];
  if ((major != 1 && major != 2 && major != 3) || minor != 0)
    throw InputError(
        fmt::format("{}: .npy format version {}.{}; expected 1.0, 2.0 or 3.0", path, major, minor));
  const int lengthBytes = major == 1 ? 2 : 4;
  if (prefixRead < static_cast<std::uintmax_t>(8) + static_cast<std::uintmax_t>(lengthBytes))
    throw InputError(
        fmt::format("{}: file of {} bytes ends in the .npy preamble; expected at "
                    "least {} bytes",
                    path, fileSize, 8 + lengthBytes));
  const std::uint64_t headerLength = littleEndian(prefix + 8, lengthBytes);
  const std::uint64_t dataOffset = 8 + lengthBytes + headerLength;
  if (dataOffset > fileSize)
    throw InputError(
        fmt::format("{}: header of {} bytes but the file has {} bytes; expected a "
                    "complete .npy header",
                    path, headerLength, fileSize));
  std::string headerText(headerLength, '\0');
  in.seekg(8 + lengthBytes);
  in.read(headerText.data(), static_cast<std::streamsize>(headerLength));
  if (!in) throw InputError(fmt::format("{}: cannot read the .npy header", path));

  const Header header = HeaderParser(headerText, path).parse();
  if (!header.descr || !header.fortranOrder || !header.shape)
    throw InputError(
        fmt::format("{}: .npy header without '{}'; expected the keys 'descr', "
                    "'fortran_order' and 'shape'",
                    path,
                    !header.descr          ? "descr"
                    : !header.fortranOrder ? "fortran_order"
                                           : "shape"));
  const std::optional<Dtype> dtype = parseDtype(*header.descr);
  if (!dtype)
    throw InputError(fmt::format("{}: dtype '{}' not supported; expected {}", path,
                                 io::excerpt(*header.descr), kDtypeList));

  NpyArray array;
  array.shape = *header.shape;
  array.dtype = *header.descr;
  // Element count and byte count with overflow checks: no allocation is larger than the file.
  const std::uint64_t available = fileSize - dataOffset;
  std::uint64_t count = 1;
  bool tooLarge = false;
  for (const std::int64_t d : array.shape) {
    const auto n = static_cast<std::uint64_t>(d);
    if (n != 0 && count > std::numeric_limits<std::uint64_t>::max() / n / 8) tooLarge = true;
    count = tooLarge ? count : count * n;
  }
  const std::uint64_t bytes = count * static_cast<std::uint64_t>(dtype->bytes);
  if (tooLarge || bytes != available)
    throw InputError(
        fmt::format("{}: data of {} bytes; expected {} bytes for shape {} of {}", path, available,
                    tooLarge ? std::string("more than 2^64") : fmt::format("{}", bytes),
                    formatNpyShape(array.shape), array.dtype));

  std::vector<unsigned char> raw(bytes);
  in.seekg(static_cast<std::streamoff>(dataOffset));
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(bytes));
  if (!in) throw InputError(fmt::format("{}: cannot read {} bytes of data", path, bytes));
  array.values.resize(count);
  if (dtype->kind != Kind::Float) array.integers.resize(count);
  for (std::uint64_t k = 0; k < count; ++k) {
    const unsigned char* at = raw.data() + k * dtype->bytes;
    const std::uint64_t word =
        dtype->bigEndian ? bigEndian(at, dtype->bytes) : littleEndian(at, dtype->bytes);
    switch (dtype->kind) {
      case Kind::Float:
        array.values[k] =
            dtype->bytes == 8
                ? std::bit_cast<double>(word)
                : static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(word)));
        break;
      case Kind::Signed: {
        // Sign-extend the dtype->bytes * 8 bit two's complement value.
        const int shift = 64 - 8 * dtype->bytes;
        array.integers[k] = static_cast<std::int64_t>(word << shift) >> shift;
        break;
      }
      case Kind::Unsigned:
        if (word > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
          throw InputError(fmt::format("{}: entry {} is {}; expected a value below 2^63", path,
                                       formatNpyIndex(array.shape, static_cast<std::int64_t>(k)),
                                       word));
        array.integers[k] = static_cast<std::int64_t>(word);
        break;
      case Kind::Bool:
        array.integers[k] = word != 0;
        break;
    }
    if (dtype->kind != Kind::Float) array.values[k] = static_cast<double>(array.integers[k]);
  }
  if (*header.fortranOrder) {
    fortranToC(array.shape, array.values);
    fortranToC(array.shape, array.integers);
  }
  return array;
}

}  // namespace bcassim
