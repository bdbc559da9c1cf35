#include "bcassim/io/MeditReader.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string_view>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"
#include "bcassim/io/TextTokens.h"

namespace bcassim {
namespace {

// The sections skipped, with the numbers each of their records holds.
struct Skipped {
  std::string_view name;
  int fields;
};
constexpr Skipped kSkipped[] = {{"Edges", 3},
                                {"Triangles", 4},
                                {"Quadrilaterals", 5},
                                {"Hexahedra", 9},
                                {"Prisms", 7},
                                {"Corners", 1},
                                {"Ridges", 1},
                                {"RequiredVertices", 1},
                                {"RequiredEdges", 1},
                                {"RequiredTriangles", 1},
                                {"RequiredQuadrilaterals", 1},
                                {"RequiredTetrahedra", 1},
                                {"Normals", 3},
                                {"NormalAtVertices", 2},
                                {"Tangents", 3},
                                {"TangentAtVertices", 2}};

class Tokens {
 public:
  Tokens(std::string text, const std::string& path)
      : text_(std::move(text)), tokens_(text_, 1, true), path_(path) {}
  Tokens(const Tokens&) = delete;  // tokens_ views text_
  Tokens& operator=(const Tokens&) = delete;

  // The next token (empty at the end of the file); comments and blanks skipped.
  std::string_view next() { return tokens_.next(); }

  long long integer(const std::string& what) {
    const std::string_view t = next();
    long long v = 0;
    if (!io::parseInt(t, v)) fail(fmt::format("{} is '{}'; expected an integer", what, text(t)));
    return v;
  }
  double real(const std::string& what) {
    const std::string_view t = next();
    double v = 0.0;
    if (!io::parseDouble(t, v) || !std::isfinite(v))
      fail(fmt::format("{} is '{}'; expected a finite number", what, text(t)));
    return v;
  }
  // A section's record count, checked against what is left of the file (each number takes at
  // least two bytes) before anything is allocated.
  long long count(std::string_view section, int fields) {
    const long long n = integer(fmt::format("the number of {}", section));
    const auto left = static_cast<long long>(tokens_.left());
    if (n < 0 || n > std::numeric_limits<int>::max() || (n > 0 && 2 * n * fields - 1 > left))
      fail(fmt::format("{} {}; expected a count in [0, 2^31) that the {} bytes left can hold",
                       section, n, left));
    return n;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}:{}: {}", path_, tokens_.line(), what));
  }
  int line() const { return tokens_.line(); }
  static std::string text(std::string_view t) {
    return t.empty() ? "the end of the file" : io::excerpt(t);
  }

 private:
  std::string text_;
  io::TextTokens tokens_;  // over text_
  const std::string& path_;
};

}  // namespace

TetMesh readMeditTetMesh(const std::string& path, MeshOrigin* origin) {
  io::requireReadableFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open file", path));
  Tokens tokens(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()),
                path);
  std::string_view word = tokens.next();
  if (word != "MeshVersionFormatted")
    tokens.fail(fmt::format("'{}'; expected 'MeshVersionFormatted' (an ASCII Medit .mesh file)",
                            Tokens::text(word)));
  const long long version = tokens.integer("MeshVersionFormatted");
  if (version < 1 || version > 4)
    tokens.fail(fmt::format("MeshVersionFormatted {}; expected 1 to 4", version));
  word = tokens.next();
  if (word != "Dimension")
    tokens.fail(fmt::format("'{}'; expected 'Dimension 3'", Tokens::text(word)));
  const long long dimension = tokens.integer("Dimension");
  if (dimension != 3)
    tokens.fail(fmt::format("Dimension {}; expected 3 (a volume mesh)", dimension));

  std::vector<double> xyz;
  std::vector<int> vertexLines, tets, refs, tetLines;
  bool haveVertices = false, haveTets = false;
  for (;;) {
    word = tokens.next();
    if (word.empty() || word == "End") break;
    if (word == "Vertices" || word == "Tetrahedra") {
      const bool vertices = word == "Vertices";
      if (vertices ? haveVertices : haveTets)
        tokens.fail(fmt::format("a second {} section; expected one", word));
      (vertices ? haveVertices : haveTets) = true;
      const long long n = tokens.count(word, vertices ? 4 : 5);
      for (long long i = 0; i < n; ++i) {
        if (vertices) {
          for (const char* axis : {"x", "y", "z"})
            xyz.push_back(tokens.real(fmt::format("vertex {} {}", i + 1, axis)));
          vertexLines.push_back(tokens.line());
          tokens.integer(fmt::format("vertex {} reference", i + 1));
          continue;
        }
        for (int k = 0; k < 4; ++k) {
          const long long v = tokens.integer(fmt::format("tetrahedron {} vertex {}", i + 1, k + 1));
          if (v < 1 || v > std::numeric_limits<int>::max())
            tokens.fail(
                fmt::format("tetrahedron {} names vertex {}; expected a number from 1 "
                            "(Medit numbers vertices from 1)",
                            i + 1, v));
          tets.push_back(static_cast<int>(v - 1));
        }
        tetLines.push_back(tokens.line());
        const long long ref = tokens.integer(fmt::format("tetrahedron {} reference", i + 1));
        if (ref < std::numeric_limits<int>::min() || ref > std::numeric_limits<int>::max())
          tokens.fail(fmt::format("tetrahedron {} reference {}; expected an int", i + 1, ref));
        refs.push_back(static_cast<int>(ref));
      }
      continue;
    }
    const Skipped* skipped = nullptr;
    for (const Skipped& s : kSkipped)
      if (s.name == word) skipped = &s;
    if (!skipped)
      tokens.fail(fmt::format(
          "section '{}' unknown; expected Vertices, Tetrahedra, another usual section (Triangles, "
          "Edges, Corners, Ridges, Normals, ...) or End",
          Tokens::text(word)));
    const std::string section(word);
    const long long n = tokens.count(section, skipped->fields);
    for (long long i = 0; i < n; ++i)
      for (int k = 0; k < skipped->fields; ++k) {
        const std::string_view t = tokens.next();
        double v = 0.0;
        if (!io::parseDouble(t, v))
          tokens.fail(fmt::format("{} {} is '{}'; expected {} numbers", section, i + 1,
                                  Tokens::text(t), skipped->fields));
      }
  }
  if (!haveTets || tets.empty())
    throw InputError(
        fmt::format("{}: no tetrahedra (a Tetrahedra section); expected a volume mesh", path));
  const auto nv = static_cast<long long>(xyz.size() / 3);
  for (size_t t = 0; t < tets.size(); ++t)
    if (tets[t] >= nv)
      throw InputError(fmt::format(
          "{}:{}: tetrahedron {} names vertex {}; expected 1 to {} (Medit numbers vertices from 1)",
          path, tetLines[t / 4], t / 4 + 1, tets[t] + 1, nv));

  TetMesh mesh;
  mesh.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(xyz.data(),
                                                                                       nv, 3);
  mesh.T = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>>(
      tets.data(), static_cast<Eigen::Index>(tets.size() / 4), 4);
  mesh.region =
      Eigen::Map<const Eigen::VectorXi>(refs.data(), static_cast<Eigen::Index>(refs.size()));
  if (origin) {
    origin->source = path;
    origin->nodeWord = "vertex";
    origin->nodeNumbers.resize(static_cast<size_t>(nv));
    for (long long i = 0; i < nv; ++i) origin->nodeNumbers[static_cast<size_t>(i)] = i + 1;
    origin->nodeLines = std::move(vertexLines);
    origin->tetWord = "tetrahedron";
    origin->tetNumbers.resize(tetLines.size());
    for (size_t t = 0; t < tetLines.size(); ++t)
      origin->tetNumbers[t] = static_cast<long long>(t) + 1;
    origin->tetLines = std::move(tetLines);
  }
  return mesh;
}

}  // namespace bcassim
