#include "bcassim/io/GmshReader.h"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {
namespace {

using io::TextLines;

// Nodes per element type, from the Gmsh reference manual (0 for types we do not know, whose
// lines are then not checked for their length).
int nodesPerElement(long long type) {
  static constexpr int kCounts[] = {0, 2,  3,  4,  4, 8,  6,  5,  3,  6,  9, 10, 27, 18, 14, 1,
                                    8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5,  6,  20, 35, 56};
  if (type >= 0 && type < static_cast<long long>(std::size(kCounts))) return kCounts[type];
  if (type == 92) return 64;
  if (type == 93) return 125;
  return 0;
}

constexpr long long kTetType = 4;

// The volume element types other than the linear tetrahedron, which would leave holes if they
// were dropped as lower-dimensional elements are; nullptr for the others.
const char* otherVolumeElement(long long type) {
  switch (type) {
    case 5:
      return "hexahedron";
    case 6:
      return "prism";
    case 7:
      return "pyramid";
    case 11:
      return "10-node tetrahedron";
    case 12:
      return "27-node hexahedron";
    case 13:
      return "18-node prism";
    case 14:
      return "14-node pyramid";
    case 17:
      return "20-node hexahedron";
    case 18:
      return "15-node prism";
    case 19:
      return "13-node pyramid";
    case 29:
      return "20-node tetrahedron";
    case 30:
      return "35-node tetrahedron";
    case 31:
      return "56-node tetrahedron";
    case 92:
      return "64-node hexahedron";
    case 93:
      return "125-node hexahedron";
    default:
      return nullptr;
  }
}
// Bounds the memory reserved from a count announced in the file, so a corrupt count fails on
// the missing lines instead of on allocation.
constexpr long long kMaxReserve = 1 << 16;

struct Parser {
  explicit Parser(const std::string& path) : in(path) {}

  TextLines in;
  enum class Format { kNone, kV1, kV2, kV41 } format = Format::kNone;
  std::vector<double> coords;  // 3 per node, in $Nodes order
  std::unordered_map<long long, int> nodeIndex;
  std::vector<int> tets;  // 4 node indices per tet
  std::vector<int> regions;
  std::vector<long long> nodeTags, elementTags;  // as the file numbers them, for messages
  std::vector<int> nodeLines, elementLines;
  std::unordered_map<long long, int> volumePhysical;  // v4.1 $Entities: volume tag -> physical tag
  bool sawNodes = false;

  // Next non-blank line; false at end of file.
  bool nextLine() {
    while (in.next())
      if (!io::isBlank(in.line())) return true;
    return false;
  }

  std::vector<std::string_view> fields() const { return io::splitBlanks(in.line()); }

  long long integer(std::string_view field, std::string_view what) const {
    long long v = 0;
    if (!io::parseInt(field, v))
      in.fail(fmt::format("expected an integer for {}, got '{}'", what, io::excerpt(field)));
    return v;
  }

  long long count(std::string_view field, std::string_view what) const {
    const long long v = integer(field, what);
    if (v < 0) in.fail(fmt::format("expected a non-negative {}, got {}", what, v));
    return v;
  }

  double coordinate(std::string_view field, long long nodeTag, char axis) const {
    double v = 0;
    if (!io::parseDouble(field, v))
      in.fail(fmt::format("expected a number for coordinate {} of node {}, got '{}'", axis, nodeTag,
                          io::excerpt(field)));
    if (!std::isfinite(v))
      in.fail(fmt::format("coordinate {} of node {} is not a finite number ('{}')", axis, nodeTag,
                          io::excerpt(field)));
    return v;
  }

  [[noreturn]] void truncated(std::string_view section, std::string_view expectation) const {
    throw InputError(fmt::format("{}: unexpected end of file in {} (line {}); {}", in.path(),
                                 io::excerpt(section), in.lineNumber(), expectation));
  }

  // A region id: a physical tag that fits the int regions are stored in.
  int region(std::string_view field, std::string_view what) const {
    const long long v = integer(field, what);
    if (v < INT_MIN || v > INT_MAX)
      in.fail(fmt::format("{} {} is out of range; expected an integer from {} to {}", what, v,
                          INT_MIN, INT_MAX));
    return static_cast<int>(v);
  }

  // Reads the line of entry `done` of `total` in `section`; a section end or end of file before
  // all announced entries is reported as truncation.
  void entryLine(std::string_view section, std::string_view what, long long total, long long done) {
    if (!nextLine()) truncated(section, fmt::format("expected {} {}, read {}", total, what, done));
    if (io::trim(in.line())[0] == '$')
      in.fail(fmt::format("expected {} {} in {}, got '{}' after {}", total, what, section,
                          io::excerpt(io::trim(in.line())), done));
  }

  void sectionEnd(std::string_view section, std::string_view end, long long total,
                  std::string_view what) {
    if (!nextLine()) truncated(section, fmt::format("expected {}", end));
    if (io::trim(in.line()) != end)
      in.fail(fmt::format("expected {} after {} {}, got '{}'", end, total, what,
                          io::excerpt(io::trim(in.line()))));
  }

  void addNode(long long tag, double x, double y, double z) {
    const int index = static_cast<int>(coords.size() / 3);
    if (!nodeIndex.emplace(tag, index).second)
      in.fail(fmt::format("node {} is defined twice", tag));
    if (index == INT_MAX) in.fail(fmt::format("more than {} nodes", INT_MAX));
    coords.insert(coords.end(), {x, y, z});
    nodeTags.push_back(tag);
    nodeLines.push_back(in.lineNumber());
  }

  void refuseOtherVolume(long long elementTag, long long type) const {
    if (const char* name = otherVolumeElement(type))
      in.fail(
          fmt::format("element {} is a {} (Gmsh type {}); expected linear tetrahedra (type 4), "
                      "the only volume elements supported",
                      elementTag, name, type));
  }

  void addTet(long long elementTag, const std::vector<std::string_view>& f, size_t first,
              int region) {
    for (size_t k = first; k < first + 4; ++k) {
      const long long tag = integer(f[k], "a node tag");
      const auto it = nodeIndex.find(tag);
      if (it == nodeIndex.end())
        in.fail(fmt::format("element {} refers to node {}, which is not defined in $Nodes",
                            elementTag, tag));
      tets.push_back(it->second);
    }
    regions.push_back(region);
    elementTags.push_back(elementTag);
    elementLines.push_back(in.lineNumber());
  }

  void meshFormat() {
    if (!nextLine()) truncated("$MeshFormat", "expected a version line");
    const auto f = fields();
    if (f.size() < 3)
      in.fail(fmt::format("expected 3 fields in the format line, got {}", f.size()));
    double version = 0;
    if (!io::parseDouble(f[0], version))
      in.fail(fmt::format("expected a version number, got '{}'", io::excerpt(f[0])));
    if (f[1] != "0")
      in.fail(
          "binary Gmsh files are not supported; expected ASCII (file-type 0), e.g. saved with "
          "gmsh -format msh22 or msh41 without -bin");
    if (version >= 2.0 && version < 3.0)
      format = Format::kV2;
    else if (f[0] == "4.1")
      format = Format::kV41;
    else
      in.fail(fmt::format("Gmsh format version {} is not supported; expected 2.2 or 4.1",
                          io::excerpt(f[0])));
    sectionEnd("$MeshFormat", "$EndMeshFormat", 1, "format line");
  }

  void requireFormat(std::string_view section) const {
    if (format == Format::kNone)
      in.fail(fmt::format("{} before $MeshFormat; expected a $MeshFormat section first", section));
  }

  // Format 1 and 2 nodes: "tag x y z" per line.
  void nodesV12(std::string_view section, std::string_view end) {
    if (!nextLine()) truncated(section, "expected the number of nodes");
    const auto header = fields();
    if (header.size() != 1)
      in.fail(fmt::format("expected 1 field (number of nodes), got {}", header.size()));
    const long long n = count(header[0], "number of nodes");
    coords.reserve(3 * std::min(n, kMaxReserve));
    for (long long i = 0; i < n; ++i) {
      entryLine(section, "nodes", n, i);
      const auto f = fields();
      if (f.size() != 4) in.fail(fmt::format("expected 4 fields in a node line, got {}", f.size()));
      const long long tag = integer(f[0], "the node tag");
      addNode(tag, coordinate(f[1], tag, 'x'), coordinate(f[2], tag, 'y'),
              coordinate(f[3], tag, 'z'));
    }
    sectionEnd(section, end, n, "nodes");
    sawNodes = true;
  }

  // Format 1: "number type physical elementary numNodes nodes..."
  void elementsV1() {
    if (!nextLine()) truncated("$ELM", "expected the number of elements");
    const auto header = fields();
    if (header.size() != 1)
      in.fail(fmt::format("expected 1 field (number of elements), got {}", header.size()));
    const long long n = count(header[0], "number of elements");
    for (long long i = 0; i < n; ++i) {
      entryLine("$ELM", "elements", n, i);
      const auto f = fields();
      if (f.size() < 5)
        in.fail(fmt::format("expected at least 5 fields in an element line, got {}", f.size()));
      const long long tag = integer(f[0], "the element number");
      const long long type = integer(f[1], "the element type");
      const int physical = region(f[2], "the physical region");
      const long long numNodes = count(f[4], "number of nodes");
      const int expectedNodes = nodesPerElement(type);
      if (expectedNodes && numNodes != expectedNodes)
        in.fail(fmt::format("element type {} has {} nodes, but the line announces {}", type,
                            expectedNodes, numNodes));
      if (numNodes > static_cast<long long>(f.size()) ||
          static_cast<long long>(f.size()) != 5 + numNodes)
        in.fail(
            fmt::format("expected {} fields in an element line, got {}", 5 + numNodes, f.size()));
      refuseOtherVolume(tag, type);
      if (type == kTetType) addTet(tag, f, 5, physical);
    }
    sectionEnd("$ELM", "$ENDELM", n, "elements");
  }

  // Format 2: "tag type numTags tags... nodes...", the first tag being the physical one.
  void elementsV2() {
    if (!nextLine()) truncated("$Elements", "expected the number of elements");
    const auto header = fields();
    if (header.size() != 1)
      in.fail(fmt::format("expected 1 field (number of elements), got {}", header.size()));
    const long long n = count(header[0], "number of elements");
    for (long long i = 0; i < n; ++i) {
      entryLine("$Elements", "elements", n, i);
      const auto f = fields();
      if (f.size() < 3)
        in.fail(fmt::format("expected at least 3 fields in an element line, got {}", f.size()));
      const long long tag = integer(f[0], "the element tag");
      const long long type = integer(f[1], "the element type");
      const long long numTags = count(f[2], "number of tags");
      const int numNodes = nodesPerElement(type);
      if (numNodes == 0) continue;
      if (numTags > static_cast<long long>(f.size()) ||
          static_cast<long long>(f.size()) != 3 + numTags + numNodes)
        in.fail(fmt::format(
            "expected {} fields in an element line (3, {} tags, {} nodes of type "
            "{}), got {}",
            numTags > static_cast<long long>(f.size()) ? std::string("more")
                                                       : fmt::format("{}", 3 + numTags + numNodes),
            numTags, numNodes, type, f.size()));
      refuseOtherVolume(tag, type);
      const int physical = numTags > 0 ? region(f[3], "the physical tag") : 0;
      if (type == kTetType) addTet(tag, f, 3 + numTags, physical);
    }
    sectionEnd("$Elements", "$EndElements", n, "elements");
  }

  // Format 4.1 entities: only volumes matter, for their physical tag.
  void entitiesV41() {
    if (!nextLine()) truncated("$Entities", "expected the entity counts");
    const auto header = fields();
    if (header.size() != 4)
      in.fail(fmt::format("expected 4 fields (entity counts), got {}", header.size()));
    long long counts[4];
    long long total = 0;
    for (int d = 0; d < 4; ++d) {
      counts[d] = count(header[d], "entity count");
      // Each entity takes a line, so counts beyond 2^40 are corrupt (and their sum would overflow).
      if (counts[d] > (1LL << 40)) in.fail(fmt::format("entity count {} is too large", counts[d]));
      total += counts[d];
    }
    long long done = 0;
    for (int dim = 0; dim < 4; ++dim) {
      for (long long i = 0; i < counts[dim]; ++i, ++done) {
        entryLine("$Entities", "entities", total, done);
        if (dim != 3) continue;
        const auto f = fields();
        if (f.size() < 8)
          in.fail(
              fmt::format("expected at least 8 fields in a volume entity line, got {}", f.size()));
        const long long tag = integer(f[0], "the volume tag");
        const long long numPhysical = count(f[7], "number of physical tags");
        if (numPhysical > static_cast<long long>(f.size()) ||
            static_cast<long long>(f.size()) < 8 + numPhysical)
          in.fail(fmt::format("expected at least {} fields in a volume entity line, got {}",
                              8 + numPhysical, f.size()));
        if (numPhysical > 0) volumePhysical[tag] = region(f[8], "physical tag");
      }
    }
    sectionEnd("$Entities", "$EndEntities", total, "entities");
  }

  // Format 4.1 nodes: blocks of "dim tag parametric count", then the tags, then the coordinates.
  void nodesV41() {
    if (!nextLine()) truncated("$Nodes", "expected the node counts");
    const auto header = fields();
    if (header.size() != 4)
      in.fail(
          fmt::format("expected 4 fields (numEntityBlocks numNodes minNodeTag maxNodeTag), "
                      "got {}",
                      header.size()));
    const long long blocks = count(header[0], "number of entity blocks");
    const long long n = count(header[1], "number of nodes");
    coords.reserve(3 * std::min(n, kMaxReserve));
    long long done = 0;
    std::vector<long long> tags;
    for (long long b = 0; b < blocks; ++b) {
      entryLine("$Nodes", "nodes", n, done);
      const auto f = fields();
      if (f.size() != 4)
        in.fail(
            fmt::format("expected 4 fields in a node block header (entityDim entityTag "
                        "parametric numNodesInBlock), got {}",
                        f.size()));
      const long long dim = integer(f[0], "the entity dimension");
      const bool parametric = integer(f[2], "the parametric flag") != 0;
      const long long inBlock = count(f[3], "number of nodes in the block");
      if (inBlock > n - done)
        in.fail(fmt::format("node blocks hold more than the {} nodes announced", n));
      tags.clear();
      for (long long i = 0; i < inBlock; ++i) {
        entryLine("$Nodes", "nodes", n, done);
        const auto t = fields();
        if (t.size() != 1) in.fail(fmt::format("expected 1 field (node tag), got {}", t.size()));
        tags.push_back(integer(t[0], "the node tag"));
      }
      const size_t expected = 3 + (parametric ? static_cast<size_t>(std::max(0LL, dim)) : 0);
      for (long long i = 0; i < inBlock; ++i, ++done) {
        entryLine("$Nodes", "nodes", n, done);
        const auto c = fields();
        if (c.size() != expected)
          in.fail(fmt::format("expected {} fields in a node coordinate line, got {}", expected,
                              c.size()));
        addNode(tags[i], coordinate(c[0], tags[i], 'x'), coordinate(c[1], tags[i], 'y'),
                coordinate(c[2], tags[i], 'z'));
      }
    }
    if (done != n) in.fail(fmt::format("node blocks hold {} nodes; expected {}", done, n));
    sectionEnd("$Nodes", "$EndNodes", n, "nodes");
    sawNodes = true;
  }

  // Format 4.1 elements: blocks of "dim tag type count", then "tag nodes..." lines.
  void elementsV41() {
    if (!nextLine()) truncated("$Elements", "expected the element counts");
    const auto header = fields();
    if (header.size() != 4)
      in.fail(
          fmt::format("expected 4 fields (numEntityBlocks numElements minElementTag "
                      "maxElementTag), got {}",
                      header.size()));
    const long long blocks = count(header[0], "number of entity blocks");
    const long long n = count(header[1], "number of elements");
    long long done = 0;
    for (long long b = 0; b < blocks; ++b) {
      entryLine("$Elements", "elements", n, done);
      const auto f = fields();
      if (f.size() != 4)
        in.fail(
            fmt::format("expected 4 fields in an element block header (entityDim entityTag "
                        "elementType numElementsInBlock), got {}",
                        f.size()));
      const long long dim = integer(f[0], "the entity dimension");
      const long long entity = integer(f[1], "the entity tag");
      const long long type = integer(f[2], "the element type");
      const long long inBlock = count(f[3], "number of elements in the block");
      if (inBlock > n - done)
        in.fail(fmt::format("element blocks hold more than the {} elements announced", n));
      const int numNodes = nodesPerElement(type);
      if (inBlock > 0 && otherVolumeElement(type))
        in.fail(
            fmt::format("an element block of {} elements of type {} ({}); expected linear "
                        "tetrahedra (type 4), the only volume elements supported",
                        inBlock, type, otherVolumeElement(type)));
      int physical = 0;
      if (dim == 3) {
        const auto it = volumePhysical.find(entity);
        if (it != volumePhysical.end()) physical = it->second;
      }
      for (long long i = 0; i < inBlock; ++i, ++done) {
        entryLine("$Elements", "elements", n, done);
        if (numNodes == 0) continue;
        const auto e = fields();
        if (static_cast<long long>(e.size()) != 1 + numNodes)
          in.fail(
              fmt::format("expected {} fields in an element line, got {}", 1 + numNodes, e.size()));
        if (type == kTetType) addTet(integer(e[0], "the element tag"), e, 1, physical);
      }
    }
    if (done != n) in.fail(fmt::format("element blocks hold {} elements; expected {}", done, n));
    sectionEnd("$Elements", "$EndElements", n, "elements");
  }

  void skipSection(std::string_view name) {
    const std::string end = fmt::format("$End{}", name.substr(1));
    while (true) {
      if (!nextLine()) truncated(name, fmt::format("expected {}", io::excerpt(end)));
      if (io::trim(in.line()) == end) return;
    }
  }

  TetMesh parse(MeshOrigin* origin) {
    bool sawElements = false;
    while (nextLine()) {
      const std::string section(io::trim(in.line()));
      if (section.empty() || section[0] != '$')
        in.fail(fmt::format("expected a section header such as $Nodes, got '{}'",
                            io::excerpt(section)));
      if (section == "$MeshFormat") {
        meshFormat();
      } else if (section == "$NOD" && format == Format::kNone) {
        format = Format::kV1;
        nodesV12("$NOD", "$ENDNOD");
      } else if (section == "$ELM" && format == Format::kV1) {
        elementsV1();
        sawElements = true;
      } else if (section == "$Nodes") {
        requireFormat(section);
        format == Format::kV41 ? nodesV41() : nodesV12("$Nodes", "$EndNodes");
      } else if (section == "$Elements") {
        requireFormat(section);
        format == Format::kV41 ? elementsV41() : elementsV2();
        sawElements = true;
      } else if (section == "$Entities" && format == Format::kV41) {
        entitiesV41();
      } else {
        skipSection(section);
      }
    }
    if (!sawNodes)
      throw InputError(fmt::format("{}: no $Nodes section; expected a Gmsh mesh", in.path()));
    if (!sawElements)
      throw InputError(fmt::format("{}: no $Elements section; expected a Gmsh mesh", in.path()));
    if (tets.empty())
      throw InputError(
          fmt::format("{}: no tetrahedra (Gmsh element type 4); expected a volume "
                      "mesh",
                      in.path()));
    TetMesh mesh;
    const Eigen::Index nv = static_cast<Eigen::Index>(coords.size() / 3);
    const Eigen::Index nt = static_cast<Eigen::Index>(regions.size());
    mesh.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
        coords.data(), nv, 3);
    mesh.T = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>>(tets.data(),
                                                                                      nt, 4);
    mesh.region = Eigen::Map<const Eigen::VectorXi>(regions.data(), nt);
    if (origin) {
      origin->source = in.path();
      origin->nodeWord = "node";
      origin->nodeNumbers = std::move(nodeTags);
      origin->nodeLines = std::move(nodeLines);
      origin->tetWord = "element";
      origin->tetNumbers = std::move(elementTags);
      origin->tetLines = std::move(elementLines);
    }
    return mesh;
  }
};

}  // namespace

TetMesh readGmshTetMesh(const std::string& path, MeshOrigin* origin) {
  return Parser(path).parse(origin);
}

}  // namespace bcassim
