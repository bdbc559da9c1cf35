#include "bcassim/io/StlReader.h"

#include <fmt/format.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"

namespace bcassim::io {
namespace {

constexpr size_t kBinaryHeader = 84;  // 80 bytes of text, then the uint32 triangle count
constexpr size_t kBinaryTriangle = 50;

// vtksys::SystemTools::DetectFileType, as vtkSTLReader uses it: text unless more than 5 % of the
// first 256 bytes are neither printable nor blanks.
bool looksLikeText(std::string_view bytes) {
  const size_t n = std::min<size_t>(bytes.size(), 256);
  size_t binary = 0;
  for (size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    if ((c < 32 && c != '\n' && c != '\r' && c != '\t' && c != '\f') || c > 126) ++binary;
  }
  return n == 0 || binary * 100 <= 5 * n;
}

// Merges coincident vertices as vtkMergePoints does: exact equality of the float coordinates
// (0 and -0 are equal), first occurrence kept, ids in order of first occurrence.
class VertexMerger {
 public:
  int insert(const std::array<float, 3>& p) {
    std::array<uint32_t, 3> key;
    for (int k = 0; k < 3; ++k) {
      const float v = p[k] == 0.0f ? 0.0f : p[k];
      std::memcpy(&key[k], &v, 4);
    }
    const auto [it, inserted] = ids_.emplace(key, static_cast<int>(points_.size()));
    if (inserted) points_.push_back(p);
    return it->second;
  }
  const std::vector<std::array<float, 3>>& points() const { return points_; }

 private:
  struct Hash {
    size_t operator()(const std::array<uint32_t, 3>& k) const {
      return (static_cast<size_t>(k[0]) * 73856093u) ^ (static_cast<size_t>(k[1]) * 19349663u) ^
             (static_cast<size_t>(k[2]) * 83492791u);
    }
  };
  std::unordered_map<std::array<uint32_t, 3>, int, Hash> ids_;
  std::vector<std::array<float, 3>> points_;
};

class StlBuilder {
 public:
  void triangle(const std::array<std::array<float, 3>, 3>& corners) {
    std::array<int, 3> ids;
    for (int k = 0; k < 3; ++k) ids[k] = merger_.insert(corners[k]);
    if (ids[0] != ids[1] && ids[0] != ids[2] && ids[1] != ids[2]) faces_.push_back(ids);
  }
  TriMesh mesh(const std::string& path) const {
    if (faces_.empty())
      throw InputError(fmt::format("{}: no triangles; expected an STL surface", path));
    TriMesh mesh;
    const auto& points = merger_.points();
    mesh.V.resize(static_cast<Eigen::Index>(points.size()), 3);
    for (size_t i = 0; i < points.size(); ++i)
      for (int k = 0; k < 3; ++k) mesh.V(static_cast<Eigen::Index>(i), k) = points[i][k];
    mesh.F.resize(static_cast<Eigen::Index>(faces_.size()), 3);
    for (size_t t = 0; t < faces_.size(); ++t)
      for (int k = 0; k < 3; ++k) mesh.F(static_cast<Eigen::Index>(t), k) = faces_[t][k];
    return mesh;
  }

 private:
  VertexMerger merger_;
  std::vector<std::array<int, 3>> faces_;
};

float littleEndianFloat(const unsigned char* p) {
  const uint32_t bits = static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
                        (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

TriMesh readBinaryStl(const std::string& path, std::string_view bytes) {
  if (bytes.size() < kBinaryHeader)
    throw InputError(
        fmt::format("{}: {} bytes; expected an ASCII STL starting with 'solid' or a "
                    "binary STL of at least {} bytes",
                    path, bytes.size(), kBinaryHeader));
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  const uint64_t count = static_cast<uint64_t>(p[80]) | (static_cast<uint64_t>(p[81]) << 8) |
                         (static_cast<uint64_t>(p[82]) << 16) |
                         (static_cast<uint64_t>(p[83]) << 24);
  const uint64_t expected = kBinaryHeader + kBinaryTriangle * count;
  if (bytes.size() != expected)
    throw InputError(
        fmt::format("{}: binary STL of {} bytes announces {} triangles; expected "
                    "84 + 50 x {} = {} bytes",
                    path, bytes.size(), count, count, expected));
  StlBuilder builder;
  for (uint64_t t = 0; t < count; ++t) {
    const unsigned char* facet = p + kBinaryHeader + kBinaryTriangle * t + 12;  // after the normal
    std::array<std::array<float, 3>, 3> corners;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) {
        const float v = littleEndianFloat(facet + 12 * c + 4 * k);
        if (!std::isfinite(v))
          throw InputError(
              fmt::format("{}: triangle {} has a non-finite coordinate ({}); "
                          "expected a finite number",
                          path, t, v));
        corners[c][k] = v;
      }
    builder.triangle(corners);
  }
  return builder.mesh(path);
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// "solid" { "facet ..." "outer loop" 3 x "vertex x y z" "endloop" "endfacet" } "endsolid", with
// optional "color" lines, possibly several solids; keywords as vtkSTLReader checks them.
TriMesh readAsciiStl(const std::string& path) {
  TextLines in(path);
  StlBuilder builder;
  enum class Expect { kSolid, kFacet, kLoop, kVertex, kEndLoop, kEndFacet } expect = Expect::kSolid;
  static constexpr const char* kExpected[] = {"solid",        "facet or endsolid", "outer loop",
                                              "vertex x y z", "endloop",           "endfacet"};
  std::array<std::array<float, 3>, 3> corners;
  int vertex = 0;
  bool sawSolid = false;
  while (in.next()) {
    const std::vector<std::string_view> f = splitBlanks(in.line());
    if (f.empty()) continue;
    const std::string keyword = lower(f[0]);
    const auto wrong = [&] {
      in.fail(fmt::format("expected '{}', got '{}'", kExpected[static_cast<int>(expect)],
                          excerpt(trim(in.line()))));
    };
    switch (expect) {
      case Expect::kSolid:
        if (keyword != "solid") wrong();
        sawSolid = true;
        expect = Expect::kFacet;
        break;
      case Expect::kFacet:
        if (keyword == "color") break;
        if (keyword == "endsolid") {
          expect = Expect::kSolid;
          break;
        }
        if (keyword != "facet") wrong();
        expect = Expect::kLoop;
        break;
      case Expect::kLoop:
        if (keyword != "outer") wrong();
        expect = Expect::kVertex;
        break;
      case Expect::kVertex: {
        if (keyword != "vertex") wrong();
        if (f.size() != 4)
          in.fail(fmt::format("expected 3 coordinates after 'vertex', got {}", f.size() - 1));
        for (int k = 0; k < 3; ++k) {
          double v = 0;
          if (!parseDouble(f[k + 1], v))
            in.fail(fmt::format("expected a number for a vertex coordinate, got '{}'",
                                excerpt(f[k + 1])));
          if (!(std::abs(v) <= std::numeric_limits<float>::max()))
            in.fail(fmt::format("vertex coordinate '{}' is not a finite 32-bit number",
                                excerpt(f[k + 1])));
          corners[vertex][k] =
              static_cast<float>(v);  // as vtkSTLReader: read as double, kept as float
        }
        if (++vertex == 3) {
          builder.triangle(corners);
          vertex = 0;
          expect = Expect::kEndLoop;
        }
        break;
      }
      case Expect::kEndLoop:
        if (keyword != "endloop") wrong();
        expect = Expect::kEndFacet;
        break;
      case Expect::kEndFacet:
        if (keyword != "endfacet") wrong();
        expect = Expect::kFacet;
        break;
    }
  }
  if (!sawSolid || expect != Expect::kSolid)
    throw InputError(fmt::format("{}: file ends at line {}; expected '{}'", path, in.lineNumber(),
                                 kExpected[static_cast<int>(expect)]));
  return builder.mesh(path);
}

}  // namespace

TriMesh readStl(const std::string& path) {
  const MappedFile file(path);
  const std::string_view bytes = file.bytes();
  const size_t first = bytes.find_first_not_of(" \t\r\n");
  const bool startsWithSolid =
      first != std::string_view::npos && lower(bytes.substr(first, 5)) == "solid";
  if (startsWithSolid && looksLikeText(bytes)) return readAsciiStl(path);
  return readBinaryStl(path, bytes);
}

}  // namespace bcassim::io
