// Typed, checked access to the YAML of a scene file: every failure becomes one InputError line
// "<file>:<line>: <key path>: <what was expected>, got <what was found>".
#pragma once
#include <yaml-cpp/yaml.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "bcassim/Types.h"

namespace bcassim::yamlio {

// Allowed values of a number, checked after parsing.
enum class Range { Any, Positive, NonNegative, AtLeastOne };

// The file a YAML tree came from, for messages, and the directory relative paths resolve against.
struct YamlSource {
  std::string file;       // as given by the user, quoted in messages
  std::string directory;  // directory of `file`
};

// 1-based line of a node, or 1 when the node carries no position (e.g. an empty document).
int lineOf(const YAML::Node& node);

// Throws InputError "<file>:<line>: <path>: <what>" (without "<path>: " when path is empty).
[[noreturn]] void failAt(const YamlSource& source, const YAML::Node& at, const std::string& path,
                         const std::string& what);

// Runs `body`, turning an InputError it throws (e.g. from a file reader or a mesh selection) into
// one prefixed with the scene position: "<file>:<line>: <path>: <original message>".
void withContext(const YamlSource& source, const YAML::Node& at, const std::string& path,
                 const std::function<void()>& body);

// How a value is described in messages: "'fast'", "a list", "a map".
std::string describe(const YAML::Node& node);

// Unit names as written in messages: "s" -> "seconds", "m" -> "metres"; others unchanged.
std::string unitWords(const std::string& unit);

// One YAML map of the scene with a fixed set of allowed keys. Construction rejects a value that is
// not a map, an unknown key and a repeated key; getters return the default for a missing key.
class MapReader {
 public:
  // `node` may be undefined or null (a section left out or left empty): every key is then missing.
  // `path` names the map in messages ("material", "fixed[0]"); empty for the top level.
  MapReader(const YamlSource& source, const YAML::Node& node, std::string path,
            const std::vector<std::string>& allowed);

  bool has(const std::string& key) const;
  // The raw value (undefined when missing).
  YAML::Node node(const std::string& key) const;
  // Position for messages about the whole map: the map itself, or `fallback` when it is missing.
  const YAML::Node& self() const { return node_; }
  std::string pathOf(const std::string& key) const;
  const YamlSource& source() const { return source_; }

  // Numbers accept YAML's .inf only where allowInfinity is set; NaN never.
  double number(const std::string& key, double fallback, const std::string& unit,
                Range range = Range::Any, bool allowInfinity = false) const;
  int integer(const std::string& key, int fallback, Range range = Range::NonNegative) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string text(const std::string& key, const std::string& fallback) const;
  // One of `choices`, e.g. "material.model: expected one of linear, stvk, got 'foo'".
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& choices) const;
  Vec3 vec3(const std::string& key, const Vec3& fallback, const std::string& unit,
            Range range = Range::Any) const;
  // A path resolved against the scene file's directory; must name an existing file.
  std::string existingFile(const std::string& key) const;

  // Fails with "<path>.<key>: <what>" at the key's value (or the map when the key is missing).
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  // Fails when `key` is present: "<path>.<key>: only for <condition>".
  void rejectUnless(bool allowed, const std::string& key, const std::string& condition) const;

 private:
  YamlSource source_;
  YAML::Node node_;
  std::string path_;
};

// Parses a scalar node as a number, integer, ... with the same messages as MapReader, for list
// elements; `path` names the element ("size[1]").
double parseNumber(const YamlSource& source, const YAML::Node& node, const std::string& path,
                   const std::string& unit, Range range = Range::Any, bool allowInfinity = false);
int parseInteger(const YamlSource& source, const YAML::Node& node, const std::string& path,
                 Range range = Range::NonNegative);
Vec3 parseVec3(const YamlSource& source, const YAML::Node& node, const std::string& path,
               const std::string& unit, Range range = Range::Any);

// Elements of a list value; an undefined or null node is an empty list, anything else fails.
std::vector<YAML::Node> listElements(const YamlSource& source, const YAML::Node& node,
                                     const std::string& path);

// Absolute, normalised form of `path` relative to `directory` (unchanged when already absolute).
std::string resolvePath(const std::string& directory, const std::string& path);

}  // namespace bcassim::yamlio
