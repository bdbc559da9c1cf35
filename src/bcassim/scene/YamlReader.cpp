#include "bcassim/scene/YamlReader.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "bcassim/Error.h"

namespace bcassim::yamlio {

namespace {

std::string joinPath(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

// A scalar shortened and stripped of control characters, so a message stays on one line.
std::string oneLine(const std::string& s) {
  std::string out;
  for (char c : s) out += (static_cast<unsigned char>(c) < 0x20) ? ' ' : c;
  if (out.size() > 60) out = out.substr(0, 57) + "...";
  return out;
}

std::string rangeText(Range range) {
  switch (range) {
    case Range::Positive:
      return "> 0";
    case Range::NonNegative:
      return ">= 0";
    case Range::AtLeastOne:
      return ">= 1";
    case Range::Any:
      break;
  }
  return "";
}

bool inRange(double v, Range range) {
  switch (range) {
    case Range::Positive:
      return v > 0;
    case Range::NonNegative:
      return v >= 0;
    case Range::AtLeastOne:
      return v >= 1;
    case Range::Any:
      break;
  }
  return true;
}

}  // namespace

int lineOf(const YAML::Node& node) {
  if (!node.IsDefined()) return 1;
  const YAML::Mark mark = node.Mark();
  return mark.line >= 0 ? mark.line + 1 : 1;
}

void failAt(const YamlSource& source, const YAML::Node& at, const std::string& path,
            const std::string& what) {
  std::string msg = source.file + ":" + std::to_string(lineOf(at)) + ": ";
  if (!path.empty()) msg += path + ": ";
  throw InputError(msg + what);
}

void withContext(const YamlSource& source, const YAML::Node& at, const std::string& path,
                 const std::function<void()>& body) {
  try {
    body();
  } catch (const InputError& e) {
    failAt(source, at, path, e.what());
  }
}

std::string describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  return "'" + oneLine(node.Scalar()) + "'";
}

std::string unitWords(const std::string& unit) {
  if (unit.empty() || unit == "-") return "";
  if (unit == "s") return "seconds";
  if (unit == "m") return "metres";
  if (unit == "N") return "newtons";
  return unit;
}

double parseNumber(const YamlSource& source, const YAML::Node& node, const std::string& path,
                   const std::string& unit, Range range, bool allowInfinity) {
  const std::string words = unitWords(unit);
  const std::string expected = "expected a number" + (words.empty() ? "" : " in " + words);
  double v = 0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, v) || std::isnan(v))
    failAt(source, node, path, expected + ", got " + describe(node));
  if (std::isinf(v) && !allowInfinity)
    failAt(source, node, path, expected + " (finite), got " + describe(node));
  if (!inRange(v, range))
    failAt(source, node, path,
           "must be " + rangeText(range) + (words.empty() ? "" : " " + words) + ", got " +
               oneLine(node.Scalar()));
  return v;
}

int parseInteger(const YamlSource& source, const YAML::Node& node, const std::string& path,
                 Range range) {
  long long v = 0;
  if (!node.IsScalar() || !YAML::convert<long long>::decode(node, v) ||
      v > std::numeric_limits<int>::max() || v < std::numeric_limits<int>::min())
    failAt(source, node, path, "expected an integer, got " + describe(node));
  if (!inRange(static_cast<double>(v), range))
    failAt(source, node, path, "must be " + rangeText(range) + ", got " + oneLine(node.Scalar()));
  return static_cast<int>(v);
}

Vec3 parseVec3(const YamlSource& source, const YAML::Node& node, const std::string& path,
               const std::string& unit, Range range) {
  const std::string words = unitWords(unit);
  if (!node.IsSequence() || node.size() != 3)
    failAt(source, node, path,
           "expected a list of 3 numbers" + (words.empty() ? "" : " in " + words) + ", got " +
               (node.IsSequence() ? "a list of " + std::to_string(node.size()) : describe(node)));
  Vec3 v;
  for (int i = 0; i < 3; ++i)
    v(i) = parseNumber(source, node[i], path + "[" + std::to_string(i) + "]", unit, range);
  return v;
}

std::vector<YAML::Node> listElements(const YamlSource& source, const YAML::Node& node,
                                     const std::string& path) {
  std::vector<YAML::Node> out;
  if (!node.IsDefined() || node.IsNull()) return out;
  if (!node.IsSequence()) failAt(source, node, path, "expected a list, got " + describe(node));
  for (const YAML::Node& e : node) out.push_back(e);
  return out;
}

// ${NAME} in a path is replaced by the environment variable NAME, taken relative to the working
// directory; ${BCASSIM_DATA} defaults to ../shared/data, where `make` finds the shared data.
static std::string expandVariables(const std::string& path) {
  std::string out;
  size_t at = 0;
  while (true) {
    const size_t open = path.find("${", at);
    const size_t close = open == std::string::npos ? open : path.find('}', open);
    if (close == std::string::npos) return out + path.substr(at);
    const std::string name = path.substr(open + 2, close - open - 2);
    const char* value = std::getenv(name.c_str());
    std::string text = value ? value : (name == "BCASSIM_DATA" ? "../shared/data" : "");
    std::error_code ec;
    if (!text.empty()) text = std::filesystem::absolute(text, ec).string();
    out += path.substr(at, open - at) + text;
    at = close + 1;
  }
}

std::string resolvePath(const std::string& directory, const std::string& rawPath) {
  const std::string path = expandVariables(rawPath);
  std::filesystem::path p(path);
  if (p.is_relative()) p = std::filesystem::path(directory) / p;
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(p, ec);
  return (ec ? p : absolute).lexically_normal().string();
}

MapReader::MapReader(const YamlSource& source, const YAML::Node& node, std::string path,
                     const std::vector<std::string>& allowed)
    // A missing key gives an "invalid" yaml-cpp node whose type queries (and assignment) throw;
    // a plain undefined node answers them.
    : source_(source),
      node_(node.IsDefined() ? node : YAML::Node(YAML::NodeType::Undefined)),
      path_(std::move(path)) {
  if (!node_.IsDefined() || node_.IsNull()) return;
  if (!node_.IsMap())
    failAt(source_, node_, path_, "expected a map of keys, got " + describe(node_));
  std::set<std::string> seen;
  for (const auto& kv : node_) {
    const YAML::Node& keyNode = kv.first;
    const std::string key = keyNode.IsScalar() ? keyNode.Scalar() : describe(keyNode);
    bool known = false;
    for (const std::string& a : allowed) known = known || key == a;
    if (!known) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      failAt(source_, keyNode, "",
             "unknown key '" + oneLine(key) + "' in " + (path_.empty() ? "scene" : path_) +
                 "; expected one of " + list);
    }
    if (!seen.insert(key).second)
      failAt(source_, keyNode, "",
             "key '" + key + "' appears twice in " + (path_.empty() ? "scene" : path_));
  }
}

bool MapReader::has(const std::string& key) const {
  return node_.IsMap() && node_[key].IsDefined() && !node_[key].IsNull();
}

YAML::Node MapReader::node(const std::string& key) const {
  if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  return node_[key];
}

std::string MapReader::pathOf(const std::string& key) const { return joinPath(path_, key); }

double MapReader::number(const std::string& key, double fallback, const std::string& unit,
                         Range range, bool allowInfinity) const {
  if (!has(key)) return fallback;
  return parseNumber(source_, node(key), pathOf(key), unit, range, allowInfinity);
}

int MapReader::integer(const std::string& key, int fallback, Range range) const {
  if (!has(key)) return fallback;
  return parseInteger(source_, node(key), pathOf(key), range);
}

bool MapReader::boolean(const std::string& key, bool fallback) const {
  if (!has(key)) return fallback;
  bool v = false;
  const YAML::Node n = node(key);
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v))
    failAt(source_, n, pathOf(key), "expected true or false, got " + describe(n));
  return v;
}

std::string MapReader::text(const std::string& key, const std::string& fallback) const {
  if (!has(key)) return fallback;
  const YAML::Node n = node(key);
  if (!n.IsScalar()) failAt(source_, n, pathOf(key), "expected a text value, got " + describe(n));
  return n.Scalar();
}

std::string MapReader::choice(const std::string& key, const std::string& fallback,
                              const std::vector<std::string>& choices) const {
  std::string v = text(key, fallback);
  for (const std::string& c : choices)
    if (v == c) return v;
  std::string list;
  for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
  failAt(source_, node(key), pathOf(key),
         "expected one of " + list + ", got " + describe(node(key)));
}

Vec3 MapReader::vec3(const std::string& key, const Vec3& fallback, const std::string& unit,
                     Range range) const {
  if (!has(key)) return fallback;
  return parseVec3(source_, node(key), pathOf(key), unit, range);
}

std::string MapReader::existingFile(const std::string& key) const {
  std::string resolved = resolvePath(source_.directory, text(key, ""));
  std::error_code ec;
  if (!has(key) || !std::filesystem::is_regular_file(resolved, ec))
    fail(key, "cannot open '" + resolved + "'");
  return resolved;
}

void MapReader::fail(const std::string& key, const std::string& what) const {
  failAt(source_, has(key) ? node(key) : node_, pathOf(key), what);
}

void MapReader::rejectUnless(bool allowed, const std::string& key,
                             const std::string& condition) const {
  if (!allowed && has(key)) fail(key, "only for " + condition);
}

}  // namespace bcassim::yamlio
