// Internal to the io module: a small XML scanner for VTK's XML files, which builds the element tree
// with each element's line and direct text, and stops at <AppendedData> as VTK does (raw bytes
// follow it). Bounded: nesting deeper than kMaxXmlDepth is refused.
#pragma once
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace bcassim::io {

constexpr int kMaxXmlDepth = 64;

// XML's white space (the S production): space, tab, line feed, carriage return.
inline bool isXmlSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;  // entity references decoded
  std::vector<int> children;                    // indices into XmlDocument::elements
  std::vector<std::pair<size_t, size_t>> text;  // direct text: [begin, end) byte ranges of the file
  int line = 0;

  // The attribute's value, or nullptr when absent.
  const std::string* attribute(std::string_view attributeName) const;
};

struct XmlDocument {
  std::vector<XmlElement> elements;         // elements[0] is the root
  size_t appendedData = std::string::npos;  // first byte after <AppendedData ...>, if present
  int appendedDataElement = -1;
};

// Scans `bytes` (the whole file; `source` names it in messages). Throws InputError naming the file
// and line, e.g. "liver.vtu:12: expected '>' to close <DataArray>, got end of file".
XmlDocument scanXml(std::string_view bytes, const std::string& source);

// `element` as it opens in the file, for messages: <DataArray Name="offsets">, <Piece>.
std::string xmlLabel(const XmlElement& element);

}  // namespace bcassim::io
