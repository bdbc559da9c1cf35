// The layout of VTK's XML data arrays, as vtkXMLDataParser reads them: binary data start with a
// header of UInt32 or UInt64 words, the byte count (uncompressed) or "blocks, block size, last
// block size, compressed size of each block" (compressed); in base64 form the compressed header and
// the blocks are encoded separately, an uncompressed header and its data together.
#include "bcassim/io/VtkXmlReader.h"

#include <fmt/format.h>
#include <lz4.h>
#include <lzma.h>
#include <zlib.h>

#include <climits>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string_view>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"
#include "bcassim/io/VtkCellTypes.h"
#include "bcassim/io/VtkScalarValues.h"
#include "bcassim/io/XmlScanner.h"

namespace bcassim::io {
namespace {

// Far above any mesh, far below what would overflow a byte count.
constexpr long long kMaxComponents = 1 << 16;
constexpr long long kMaxValues = 1LL << 40;
// VTK writes blocks of 32 KiB; a larger block is allowed up to this size, which bounds what one
// block may allocate before its data prove it.
constexpr unsigned long long kMaxBlockBytes = 1ULL << 26;

int base64Value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// Sequential reads of binary data, raw or base64. A base64 source decodes 4 characters at a time;
// restart() drops what is left of the current group, as VTK does between a compressed header and
// its blocks (encoded separately).
class ByteSource {
 public:
  ByteSource(std::string_view data, bool base64) : data_(data), base64_(base64) {}

  // Appends the next n bytes to `out`; false when the data end first. Throws std::invalid_argument
  // on a character that is not base64.
  bool read(size_t n, std::string& out) {
    if (!base64_) {
      if (data_.size() - pos_ < n) return false;
      out.reserve(out.size() + n);  // proved by the data: no repeated growth
      out.append(data_.substr(pos_, n));
      pos_ += n;
      return true;
    }
    // Each group of 4 characters gives at most 3 bytes: refuse early what cannot be there.
    if (n > pending_.size() && (n - pending_.size()) / 3 > (data_.size() - pos_) / 4 + 1)
      return false;
    pending_.reserve(n + 3);
    while (pending_.size() < n) {
      if (!decodeGroup()) return false;
    }
    out.append(pending_, 0, n);
    pending_.erase(0, n);
    return true;
  }
  void restart() { pending_.clear(); }

 private:
  bool decodeGroup() {
    int values[4];
    int got = 0;
    int padding = 0;
    while (got < 4) {
      if (pos_ >= data_.size()) return false;
      const char c = data_[pos_++];
      if (isXmlSpace(c)) continue;
      if (c == '=' && got >= 2) {
        ++padding;
        values[got++] = 0;
        continue;
      }
      const int v = base64Value(c);
      if (v < 0 || padding > 0) throw std::invalid_argument("base64");
      values[got++] = v;
    }
    const unsigned long triple = (static_cast<unsigned long>(values[0]) << 18) |
                                 (static_cast<unsigned long>(values[1]) << 12) |
                                 (static_cast<unsigned long>(values[2]) << 6) |
                                 static_cast<unsigned long>(values[3]);
    pending_ += static_cast<char>((triple >> 16) & 0xff);
    if (padding < 2) pending_ += static_cast<char>((triple >> 8) & 0xff);
    if (padding < 1) pending_ += static_cast<char>(triple & 0xff);
    return true;
  }

  std::string_view data_;
  bool base64_;
  size_t pos_ = 0;
  std::string pending_;
};

enum class Compressor { kNone, kZlib, kLz4, kLzma };

std::optional<VtkScalar> scalarNamed(std::string_view name) {
  using S = VtkScalar;
  static const std::pair<const char*, S> kTypes[] = {
      {"Int8", S::kInt8},       {"UInt8", S::kUInt8},   {"Int16", S::kInt16},
      {"UInt16", S::kUInt16},   {"Int32", S::kInt32},   {"UInt32", S::kUInt32},
      {"Int64", S::kInt64},     {"UInt64", S::kUInt64}, {"Float32", S::kFloat32},
      {"Float64", S::kFloat64}, {"Char", S::kInt8},     {"UChar", S::kUInt8}};
  for (const auto& [typeName, scalar] : kTypes)
    if (name == typeName) return scalar;
  return std::nullopt;
}

class XmlReader {
 public:
  XmlReader(std::string_view bytes, std::string source, VtkDataset::Kind expected)
      : bytes_(bytes), expected_(expected) {
    out_.kind = expected;
    out_.source = std::move(source);
  }

  VtkDataset read() {
    const size_t first = bytes_.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos || bytes_[first] != '<') notThisKind();
    doc_ = scanXml(bytes_, out_.source);
    const XmlElement& root = doc_.elements[0];
    if (root.name != "VTKFile") notThisKind();
    const std::string* type = root.attribute("type");
    if (!type || *type != kindName()) notThisKind();
    readFileAttributes(root);
    const XmlElement* grid = child(root, kindName());
    if (!grid) fail(root, fmt::format("no <{}> element; expected one", kindName()));
    std::vector<const XmlElement*> pieces = children(*grid, "Piece");
    if (pieces.size() != 1)
      fail(*grid, fmt::format("{} <Piece> elements; expected 1", pieces.size()));
    readPiece(*pieces[0]);
    return std::move(out_);
  }

 private:
  bool isGrid() const { return expected_ == VtkDataset::Kind::kUnstructuredGrid; }
  const char* kindName() const { return isGrid() ? "UnstructuredGrid" : "PolyData"; }

  [[noreturn]] void notThisKind() const {
    throw InputError(fmt::format("{}: not a VTK XML {}; expected <VTKFile type=\"{}\">",
                                 out_.source, isGrid() ? "unstructured grid" : "polydata file",
                                 kindName()));
  }
  [[noreturn]] void fail(const XmlElement& e, const std::string& what) const {
    throw InputError(fmt::format("{}:{}: {}: {}", out_.source, e.line, xmlLabel(e), what));
  }

  const XmlElement* child(const XmlElement& e, std::string_view name) const {
    for (int c : e.children)
      if (doc_.elements[c].name == name) return &doc_.elements[c];
    return nullptr;
  }
  std::vector<const XmlElement*> children(const XmlElement& e, std::string_view name) const {
    std::vector<const XmlElement*> found;
    for (int c : e.children)
      if (doc_.elements[c].name == name) found.push_back(&doc_.elements[c]);
    return found;
  }
  const XmlElement* namedArray(const XmlElement& e, std::string_view name) const {
    for (const XmlElement* a : children(e, "DataArray"))
      if (const std::string* n = a->attribute("Name"); n && *n == name) return a;
    return nullptr;
  }

  // An integer attribute in [0, max]; `fallback` when absent (required when fallback < 0).
  long long integerAttribute(const XmlElement& e, const char* name, long long max,
                             long long fallback) const {
    const std::string* value = e.attribute(name);
    if (!value) {
      if (fallback < 0) fail(e, fmt::format("no {} attribute; expected one", name));
      return fallback;
    }
    long long v = 0;
    if (!parseInt(trim(*value), v) || v < 0 || v > max)
      fail(e,
           fmt::format("{}=\"{}\"; expected an integer from 0 to {}", name, excerpt(*value), max));
    return v;
  }

  void readFileAttributes(const XmlElement& root) {
    if (const std::string* order = root.attribute("byte_order")) {
      if (*order != "LittleEndian" && *order != "BigEndian")
        fail(root,
             fmt::format("byte_order=\"{}\"; expected LittleEndian or BigEndian", excerpt(*order)));
      bigEndian_ = *order == "BigEndian";
    }
    if (const std::string* header = root.attribute("header_type")) {
      if (*header != "UInt32" && *header != "UInt64")
        fail(root, fmt::format("header_type=\"{}\"; expected UInt32 or UInt64", excerpt(*header)));
      headerBytes_ = *header == "UInt64" ? 8 : 4;
    }
    if (const std::string* compressor = root.attribute("compressor");
        compressor && !compressor->empty()) {
      if (*compressor == "vtkZLibDataCompressor")
        compressor_ = Compressor::kZlib;
      else if (*compressor == "vtkLZ4DataCompressor")
        compressor_ = Compressor::kLz4;
      else if (*compressor == "vtkLZMADataCompressor")
        compressor_ = Compressor::kLzma;
      else
        fail(root, fmt::format("compressor=\"{}\"; expected vtkZLibDataCompressor, "
                               "vtkLZ4DataCompressor or vtkLZMADataCompressor",
                               excerpt(*compressor)));
    }
    if (doc_.appendedData != std::string::npos) {
      const XmlElement& appended = doc_.elements[doc_.appendedDataElement];
      const std::string* encoding = appended.attribute("encoding");
      if (encoding && *encoding != "raw" && *encoding != "base64")
        fail(appended, fmt::format("encoding=\"{}\"; expected raw or base64", excerpt(*encoding)));
      appendedRaw_ = encoding && *encoding == "raw";
      // The data start after the first non-blank character, an underscore (VTK reads any other
      // character as data).
      size_t p = doc_.appendedData;
      while (p < bytes_.size() && isXmlSpace(bytes_[p])) ++p;
      appendedStart_ = p < bytes_.size() && bytes_[p] == '_' ? p + 1 : p;
    }
  }

  void readPiece(const XmlElement& piece) {
    const long long numPoints = integerAttribute(piece, "NumberOfPoints", INT_MAX, -1);
    const XmlElement* points = child(piece, "Points");
    if (numPoints > 0 && !points) fail(piece, "no <Points>; expected the points");
    if (numPoints > 0) {
      const std::vector<const XmlElement*> arrays = children(*points, "DataArray");
      if (arrays.empty()) fail(*points, "no <DataArray>; expected the coordinates");
      // Allocated only once the data have proved the count (decodeArray calls `reserve` then).
      decodeArray(
          *arrays[0], numPoints, 3, Check::kFinite,
          [&](long long i, double x) { out_.points(i / 3, i % 3) = x; },
          [&](long long) { out_.points.resize(numPoints, 3); });
    }
    long long numCells = 0;
    if (isGrid()) {
      numCells = integerAttribute(piece, "NumberOfCells", INT_MAX, -1);
      readCells(piece, "Cells", numCells, numPoints, "cell", 1, out_.cells, true);
    } else {
      static const char* const kBlocks[][3] = {{"Verts", "NumberOfVerts", "vertex cell"},
                                               {"Lines", "NumberOfLines", "line"},
                                               {"Polys", "NumberOfPolys", "polygon"},
                                               {"Strips", "NumberOfStrips", "triangle strip"}};
      static const int kMinPoints[] = {1, 2, 3, 3};
      VtkCells* blocks[] = {&out_.verts, &out_.lines, &out_.polys, &out_.strips};
      for (int b = 0; b < 4; ++b) {
        const long long n = integerAttribute(piece, kBlocks[b][1], INT_MAX, 0);
        readCells(piece, kBlocks[b][0], n, numPoints, kBlocks[b][2], kMinPoints[b], *blocks[b],
                  false);
        numCells += n;
      }
    }
    if (const XmlElement* cellData = child(piece, "CellData"))
      for (const XmlElement* a : children(*cellData, "DataArray")) readCellArray(*a, numCells);
  }

  void readCells(const XmlElement& piece, const char* element, long long n, long long numPoints,
                 const char* cellWord, int minPoints, VtkCells& cells, bool typed) {
    if (n == 0) return;
    const XmlElement* holder = child(piece, element);
    if (!holder) fail(piece, fmt::format("no <{}>; expected the {} cells", element, n));
    const XmlElement* offsetsArray = namedArray(*holder, "offsets");
    const XmlElement* connArray = namedArray(*holder, "connectivity");
    if (!offsetsArray || !connArray)
      fail(*holder, "expected DataArrays named \"connectivity\" and \"offsets\"");
    if (typed) out_.cellsLine = holder->line;
    // offsets[c] is where cell c ends in the connectivity; each value goes straight where it is
    // kept, once the data have proved the count (no intermediate array).
    cells.offsets.assign(1, 0);
    decodeArray(*offsetsArray, n, 1, Check::kInteger, [&](long long c, double end) {
      const double previous = static_cast<double>(cells.offsets.back());
      if (!(end >= previous) || end > static_cast<double>(kMaxValues))
        fail(*offsetsArray, fmt::format("offset {} is {}; expected at least {} (offsets never "
                                        "decrease)",
                                        c, end, previous));
      cells.offsets.push_back(static_cast<long long>(end));
    });
    long long cell = 0;
    cells.connectivity.clear();
    decodeArray(*connArray, cells.offsets.back(), 1, Check::kInteger, [&](long long i, double id) {
      while (cells.offsets[cell + 1] <= i) ++cell;
      if (!(id >= 0 && id < static_cast<double>(numPoints)))
        fail(*connArray,
             fmt::format("{} {} refers to point {}; the file has {} points{}", cellWord, cell, id,
                         numPoints, numPoints > 0 ? fmt::format(" (0 to {})", numPoints - 1) : ""));
      cells.connectivity.push_back(static_cast<int>(id));
    });
    if (!typed) {
      for (long long c = 0; c < n; ++c)
        if (cells.count(c) < minPoints)
          fail(*offsetsArray, fmt::format("{} {} has {} point ids; expected at least {}", cellWord,
                                          c, cells.count(c), minPoints));
      return;
    }
    const XmlElement* typesArray = namedArray(*holder, "types");
    if (!typesArray) fail(*holder, "expected a DataArray named \"types\"");
    cells.types.clear();
    decodeArray(*typesArray, n, 1, Check::kInteger, [&](long long c, double value) {
      const VtkCellType* type =
          value >= 0 && value < 256 ? findVtkCellType(static_cast<long long>(value)) : nullptr;
      if (!type)
        fail(*typesArray, fmt::format("cell {} has the unknown VTK cell type {}", c, value));
      cells.types.push_back(static_cast<unsigned char>(type->id));
      const std::string expected = vtkCellCountExpectation(*type, cells.count(c));
      if (!expected.empty())
        throw InputError(fmt::format("{}: cell {} ({}) has {} point ids; expected {}",
                                     out_.cellLocation(c), c, describeVtkCellType(*type),
                                     cells.count(c), expected));
    });
  }

  void readCellArray(const XmlElement& e, long long numCells) {
    VtkArray array;
    if (const std::string* name = e.attribute("Name")) array.name = *name;
    array.tuples = numCells;
    const std::string* type = e.attribute("type");
    if (type && *type == "String") {
      array.numeric = false;
    } else {
      array.components =
          static_cast<int>(integerAttribute(e, "NumberOfComponents", kMaxComponents, 1));
      array.values = readArray(e, numCells, 0, Check::kNone);
    }
    out_.cellArrays.push_back(std::move(array));
  }

  // What readArray requires of the values besides their count.
  enum class Check { kNone, kFinite, kInteger };

  // The values of DataArray `e`, `tuples` tuples of `components` (0: as the element says), as
  // doubles.
  std::vector<double> readArray(const XmlElement& e, long long tuples, long long components,
                                Check check) {
    std::vector<double> values;
    decodeArray(
        e, tuples, components, check, [&](long long, double v) { values.push_back(v); },
        [&](long long count) { values.reserve(static_cast<size_t>(count)); });
    return values;
  }

  // Decodes DataArray `e` (`tuples` tuples of `components`, 0: as the element says), calling
  // reserve(count) once the data have proved the count (before that, nothing is allocated from
  // it), then sink(index, value) for each value in order.
  template <class Sink, class Reserve = void (*)(long long)>
  void decodeArray(
      const XmlElement& e, long long tuples, long long components, Check check, Sink&& sink,
      Reserve&& reserve = [](long long) {}) {
    const bool finite = check == Check::kFinite;
    const std::string* typeName = e.attribute("type");
    if (!typeName) fail(e, "no type attribute; expected one such as Float64 or Int64");
    const std::optional<VtkScalar> type = scalarNamed(*typeName);
    if (!type)
      fail(e, fmt::format("type=\"{}\"; expected Int8, UInt8, Int16, UInt16, Int32, UInt32, "
                          "Int64, UInt64, Float32 or Float64",
                          excerpt(*typeName)));
    if (check == Check::kInteger && !vtkScalarIsInteger(*type))
      fail(e,
           fmt::format("type=\"{}\"; expected an integer type such as Int64", excerpt(*typeName)));
    const long long declared = integerAttribute(e, "NumberOfComponents", kMaxComponents, 1);
    if (declared == 0) fail(e, "NumberOfComponents=\"0\"; expected at least 1");
    if (components > 0 && declared != components)
      fail(e, fmt::format("NumberOfComponents=\"{}\"; expected {}", declared, components));
    if (e.attribute("NumberOfTuples") &&
        integerAttribute(e, "NumberOfTuples", kMaxValues, 0) != tuples)
      fail(e, fmt::format("NumberOfTuples=\"{}\"; expected {}", *e.attribute("NumberOfTuples"),
                          tuples));
    if (tuples > kMaxValues / declared)
      fail(e, fmt::format("{} tuples of {} components; expected at most {} values", tuples,
                          declared, kMaxValues));
    const long long count = tuples * declared;
    const std::string* format = e.attribute("format");
    if (!format) fail(e, "no format attribute; expected ascii, binary or appended");
    if (*format == "ascii") return decodeAscii(e, *type, count, finite, sink, reserve);
    if (*format != "binary" && *format != "appended")
      fail(e, fmt::format("format=\"{}\"; expected ascii, binary or appended", excerpt(*format)));
    const int wordBytes = vtkScalarBytes(*type);
    const std::string bytes =
        binaryData(e, *format == "appended", static_cast<unsigned long long>(count) * wordBytes,
                   count, *typeName);
    reserve(count);
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
    for (long long i = 0; i < count; ++i) {
      const double v = decodeVtkScalar(p + i * wordBytes, *type, bigEndian_);
      if (finite && !std::isfinite(v))
        fail(e, fmt::format("point {} has a non-finite coordinate ({})", i / 3, v));
      sink(i, v);
    }
  }

  template <class Sink, class Reserve>
  void decodeAscii(const XmlElement& e, VtkScalar type, long long count, bool finite, Sink& sink,
                   Reserve& reserve) {
    size_t textBytes = 0;
    for (const auto& [begin, end] : e.text) textBytes += end - begin;
    const size_t most = textBytes / 2 + 1;  // a value and its separator take 2 bytes at least
    if (static_cast<unsigned long long>(count) > most)
      fail(e, fmt::format("{} ascii values cannot fit in its {} bytes of text", count, textBytes));
    reserve(count);
    long long read = 0;
    int line = e.line;
    for (const auto& [begin, end] : e.text) {
      size_t p = begin;
      while (p < end) {
        while (p < end && isXmlSpace(bytes_[p])) line += bytes_[p++] == '\n';
        if (p == end) break;
        const size_t start = p;
        while (p < end && !isXmlSpace(bytes_[p])) ++p;
        const std::string_view token(bytes_.data() + start, p - start);
        if (read == count) fail(e, fmt::format("holds more than the {} values expected", count));
        double v = 0;
        const std::string why = parseVtkScalar(token, type, v);
        const auto failAt = [&](const std::string& what) {
          throw InputError(fmt::format("{}:{}: {}: {}", out_.source, line, xmlLabel(e), what));
        };
        if (!why.empty()) failAt(fmt::format("value '{}': {}", excerpt(token), why));
        if (finite && !std::isfinite(v))
          failAt(fmt::format("value '{}' is not a finite number", excerpt(token)));
        sink(read++, v);
      }
    }
    if (read != count) fail(e, fmt::format("holds {} values; expected {}", read, count));
  }

  unsigned long long headerWord(const std::string& bytes, size_t index) const {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + index * headerBytes_);
    unsigned long long v = 0;
    for (int k = 0; k < headerBytes_; ++k) {
      const int byte = bigEndian_ ? k : headerBytes_ - 1 - k;
      v = (v << 8) | p[byte];
    }
    return v;
  }

  // The `expected` bytes of a binary or appended DataArray, decoded and decompressed.
  std::string binaryData(const XmlElement& e, bool appended, unsigned long long expected,
                         long long count, const std::string& typeName) {
    std::string_view data;
    std::string text;
    bool base64 = true;
    if (appended) {
      if (appendedStart_ == std::string::npos)
        fail(e, "format=\"appended\" but the file has no <AppendedData>");
      const long long offset = integerAttribute(e, "offset", LLONG_MAX, -1);
      if (static_cast<unsigned long long>(offset) > bytes_.size() - appendedStart_)
        fail(e, fmt::format("offset=\"{}\" is beyond the {} bytes of appended data", offset,
                            bytes_.size() - appendedStart_));
      data = std::string_view(bytes_).substr(appendedStart_ + static_cast<size_t>(offset));
      base64 = !appendedRaw_;
    } else if (e.text.size() == 1) {  // the usual case: read in place (blanks are skipped)
      data = std::string_view(bytes_).substr(e.text[0].first, e.text[0].second - e.text[0].first);
    } else {
      for (const auto& [begin, end] : e.text) text.append(bytes_.substr(begin, end - begin));
      data = text;
    }
    ByteSource source(data, base64);
    const std::string what = fmt::format("{} values of {}", count, typeName);
    try {
      return compressor_ == Compressor::kNone ? uncompressed(e, source, expected, what)
                                              : compressed(e, source, expected, what);
    } catch (const std::invalid_argument&) {
      fail(e, "its data hold a character that is not base64");
    }
  }

  std::string uncompressed(const XmlElement& e, ByteSource& source, unsigned long long expected,
                           const std::string& what) {
    std::string header;
    if (!source.read(headerBytes_, header)) fail(e, "its data end before their size header");
    const unsigned long long size = headerWord(header, 0);
    if (size != expected)
      fail(e, fmt::format("its data header says {} bytes; expected {} ({})", size, expected, what));
    std::string bytes;
    if (!source.read(static_cast<size_t>(size), bytes))
      fail(e, fmt::format("its data end before the {} bytes their header announces", size));
    return bytes;
  }

  std::string compressed(const XmlElement& e, ByteSource& source, unsigned long long expected,
                         const std::string& what) {
    std::string header;
    if (!source.read(3 * static_cast<size_t>(headerBytes_), header))
      fail(e, "its data end before their compression header");
    const unsigned long long blocks = headerWord(header, 0);
    const unsigned long long blockSize = headerWord(header, 1);
    const unsigned long long lastSize = headerWord(header, 2);
    if (blocks > 0 && (blockSize == 0 || blockSize > kMaxBlockBytes || lastSize > blockSize))
      fail(e, fmt::format("compression header: block size {} and last block size {}; expected a "
                          "block size from 1 to {} and a last block no larger",
                          blockSize, lastSize, kMaxBlockBytes));
    if (blocks > expected / std::max(blockSize, 1ULL) + 1)
      fail(e, fmt::format("compression header: {} blocks of {} bytes; expected {} bytes ({})",
                          blocks, blockSize, expected, what));
    const unsigned long long total =
        blocks == 0 ? 0 : (blocks - 1) * blockSize + (lastSize > 0 ? lastSize : blockSize);
    if (total != expected)
      fail(e, fmt::format("compression header: {} bytes in {} blocks; expected {} ({})", total,
                          blocks, expected, what));
    std::string sizes;
    if (!source.read(static_cast<size_t>(blocks) * headerBytes_, sizes))
      fail(e, fmt::format("its data end inside the compression header of {} blocks", blocks));
    source.restart();
    std::string bytes, block, decompressed;
    // Capacity only (no page is touched until data are written), bounded as a lying header could
    // make `expected` as large as 2^43 bytes.
    bytes.reserve(static_cast<size_t>(std::min<unsigned long long>(expected, 1ULL << 26)));
    for (unsigned long long b = 0; b < blocks; ++b) {
      const unsigned long long compressedSize = headerWord(sizes, b);
      const unsigned long long blockBytes = b + 1 == blocks && lastSize > 0 ? lastSize : blockSize;
      block.clear();
      if (compressedSize > INT_MAX || !source.read(static_cast<size_t>(compressedSize), block))
        fail(e, fmt::format("its data end inside compressed block {} of {} ({} bytes)", b, blocks,
                            compressedSize));
      if (!decompress(block, blockBytes, decompressed))
        fail(e, fmt::format("compressed block {} of {} does not decompress to its {} bytes", b,
                            blocks, blockBytes));
      bytes += decompressed;
    }
    return bytes;
  }

  // `size` bytes decompressed from `in` into `out` (a buffer reused from block to block); false
  // when `in` is not a block of that size.
  bool decompress(const std::string& in, unsigned long long size, std::string& out) const {
    out.resize(static_cast<size_t>(size));
    auto* dst = reinterpret_cast<unsigned char*>(out.data());
    const auto* src = reinterpret_cast<const unsigned char*>(in.data());
    switch (compressor_) {
      case Compressor::kZlib: {
        uLongf produced = static_cast<uLongf>(size);
        return uncompress(dst, &produced, src, static_cast<uLong>(in.size())) == Z_OK &&
               produced == size;
      }
      case Compressor::kLz4:
        return LZ4_decompress_safe(in.data(), reinterpret_cast<char*>(dst),
                                   static_cast<int>(in.size()),
                                   static_cast<int>(size)) == static_cast<int>(size);
      case Compressor::kLzma: {
        uint64_t memoryLimit = 1ULL << 28;
        size_t inPos = 0, outPos = 0;
        return lzma_stream_buffer_decode(&memoryLimit, 0, nullptr, src, &inPos, in.size(), dst,
                                         &outPos, static_cast<size_t>(size)) == LZMA_OK &&
               outPos == size;
      }
      case Compressor::kNone:
        break;
    }
    return false;
  }

  const std::string_view bytes_;
  const VtkDataset::Kind expected_;
  XmlDocument doc_;
  bool bigEndian_ = false;
  int headerBytes_ = 4;
  Compressor compressor_ = Compressor::kNone;
  bool appendedRaw_ = false;
  size_t appendedStart_ = std::string::npos;
  VtkDataset out_;
};

}  // namespace

VtkDataset readVtkXml(const std::string& path, VtkDataset::Kind expected) {
  const MappedFile file(path);
  return XmlReader(file.bytes(), path, expected).read();
}

}  // namespace bcassim::io
