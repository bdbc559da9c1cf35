// Enough XML for VTK files: elements, attributes with the predefined and numeric entity references,
// text, comments, processing instructions, CDATA and a DOCTYPE line; no namespaces or DTDs.
#include "bcassim/io/XmlScanner.h"

#include <fmt/format.h>

#include <cctype>

#include "bcassim/Error.h"
#include "bcassim/io/TextLines.h"

namespace bcassim::io {
namespace {

bool isNameChar(char c) {
  const auto u = static_cast<unsigned char>(c);
  return std::isalnum(u) || c == '_' || c == '-' || c == '.' || c == ':' || u >= 0x80;
}

void appendUtf8(std::string& out, unsigned long code) {
  if (code < 0x80) {
    out += static_cast<char>(code);
  } else if (code < 0x800) {
    out += static_cast<char>(0xc0 | (code >> 6));
    out += static_cast<char>(0x80 | (code & 0x3f));
  } else if (code < 0x10000) {
    out += static_cast<char>(0xe0 | (code >> 12));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
    out += static_cast<char>(0x80 | (code & 0x3f));
  } else {
    out += static_cast<char>(0xf0 | (code >> 18));
    out += static_cast<char>(0x80 | ((code >> 12) & 0x3f));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
    out += static_cast<char>(0x80 | (code & 0x3f));
  }
}

class Scanner {
 public:
  Scanner(std::string_view bytes, const std::string& source) : data_(bytes), source_(source) {}

  XmlDocument scan() {
    std::vector<int> open;
    while (pos_ < data_.size()) {
      if (data_[pos_] != '<') {
        const size_t start = pos_;
        while (pos_ < data_.size() && data_[pos_] != '<') advance();
        if (!open.empty()) {
          doc_.elements[open.back()].text.emplace_back(start, pos_);
        } else {
          for (size_t p = start; p < pos_; ++p)
            if (!isXmlSpace(data_[p]))
              fail(fmt::format("text '{}' outside the root element",
                               excerpt(data_.substr(p, pos_ - p))));
        }
        continue;
      }
      if (startsWith("<?")) {
        skipPast("?>", "a processing instruction");
      } else if (startsWith("<!--")) {
        skipPast("-->", "a comment");
      } else if (startsWith("<![CDATA[")) {
        if (open.empty()) fail("CDATA outside the root element");
        const size_t start = pos_ + 9;
        skipPast("]]>", "CDATA");
        doc_.elements[open.back()].text.emplace_back(start, pos_ - 3);
      } else if (startsWith("<!")) {
        skipPast(">", "a declaration");
      } else if (startsWith("</")) {
        closeTag(open);
      } else {
        if (!open.empty() || doc_.elements.empty()) {
          if (openTag(open)) return std::move(doc_);  // <AppendedData>: raw bytes follow
        } else {
          fail("a second root element; expected one <VTKFile>");
        }
      }
    }
    if (doc_.elements.empty()) fail("no XML element; expected <VTKFile>");
    if (!open.empty())
      fail(fmt::format("file ends inside {}; expected </{}>", xmlLabel(doc_.elements[open.back()]),
                       doc_.elements[open.back()].name));
    return std::move(doc_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}:{}: {}", source_, line_, what));
  }
  void advance() {
    if (data_[pos_] == '\n') ++line_;
    ++pos_;
  }
  bool startsWith(std::string_view s) const { return data_.substr(pos_, s.size()) == s; }
  void skipPast(std::string_view end, std::string_view what) {
    const size_t found = data_.find(end, pos_);
    if (found == std::string_view::npos) fail(fmt::format("file ends inside {}", what));
    while (pos_ < found + end.size()) advance();
  }
  void skipSpace() {
    while (pos_ < data_.size() && isXmlSpace(data_[pos_])) advance();
  }
  std::string name(std::string_view what) {
    const size_t start = pos_;
    while (pos_ < data_.size() && isNameChar(data_[pos_])) ++pos_;
    if (pos_ == start)
      fail(fmt::format("expected {}, got '{}'", what, excerpt(data_.substr(pos_, 1))));
    return std::string(data_.substr(start, pos_ - start));
  }

  std::string attributeValue() {
    if (pos_ >= data_.size() || (data_[pos_] != '"' && data_[pos_] != '\''))
      fail("expected a quoted attribute value");
    const char quote = data_[pos_++];
    std::string value;
    while (true) {
      if (pos_ >= data_.size()) fail("file ends inside an attribute value");
      const char c = data_[pos_];
      if (c == quote) break;
      if (c == '<') fail("'<' inside an attribute value");
      if (c == '&') {
        const size_t semicolon = data_.find(';', pos_);
        if (semicolon == std::string_view::npos || semicolon - pos_ > 12)
          fail("'&' without an entity reference in an attribute value");
        const std::string_view entity = data_.substr(pos_ + 1, semicolon - pos_ - 1);
        if (entity == "lt")
          value += '<';
        else if (entity == "gt")
          value += '>';
        else if (entity == "amp")
          value += '&';
        else if (entity == "quot")
          value += '"';
        else if (entity == "apos")
          value += '\'';
        else if (entity.size() > 1 && entity[0] == '#')
          numericEntity(entity, value);
        else
          fail(fmt::format("unknown entity '&{};'", excerpt(entity)));
        pos_ = semicolon + 1;
        continue;
      }
      value += c;
      advance();
    }
    ++pos_;
    return value;
  }

  void numericEntity(std::string_view entity, std::string& value) {
    const bool hex = entity[1] == 'x' || entity[1] == 'X';
    const std::string_view digits = entity.substr(hex ? 2 : 1);
    unsigned long code = 0;
    for (char c : digits) {
      const auto u = static_cast<unsigned char>(c);
      if (hex ? !std::isxdigit(u) : !std::isdigit(u))
        fail(fmt::format("bad character reference '&{};'", excerpt(entity)));
      code = code * (hex ? 16 : 10) +
             static_cast<unsigned long>(std::isdigit(u) ? c - '0' : std::tolower(u) - 'a' + 10);
    }
    if (digits.empty() || code == 0 || code > 0x10ffff)
      fail(fmt::format("bad character reference '&{};'", excerpt(entity)));
    appendUtf8(value, code);
  }

  // Returns true when the tag opened <AppendedData>, after which the scan stops.
  bool openTag(std::vector<int>& open) {
    ++pos_;
    XmlElement element;
    element.line = line_;
    element.name = name("an element name after '<'");
    while (true) {
      skipSpace();
      if (pos_ >= data_.size())
        fail(fmt::format("file ends inside the tag <{}>", excerpt(element.name)));
      if (data_[pos_] == '>' || startsWith("/>")) break;
      std::string attributeName =
          name(fmt::format("an attribute name in <{}>", excerpt(element.name)));
      skipSpace();
      if (pos_ >= data_.size() || data_[pos_] != '=')
        fail(fmt::format("expected '=' after attribute {} of <{}>", excerpt(attributeName),
                         excerpt(element.name)));
      ++pos_;
      skipSpace();
      std::string value = attributeValue();
      if (element.attribute(attributeName))
        fail(fmt::format("attribute {} appears twice in <{}>", excerpt(attributeName),
                         excerpt(element.name)));
      element.attributes.emplace_back(std::move(attributeName), std::move(value));
    }
    const bool selfClosing = data_[pos_] == '/';
    pos_ += selfClosing ? 2 : 1;
    const int index = static_cast<int>(doc_.elements.size());
    if (!open.empty()) doc_.elements[open.back()].children.push_back(index);
    const bool appended = element.name == "AppendedData";
    doc_.elements.push_back(std::move(element));
    if (appended) {
      doc_.appendedData = pos_;
      doc_.appendedDataElement = index;
      return true;
    }
    if (!selfClosing) {
      if (static_cast<int>(open.size()) >= kMaxXmlDepth)
        fail(fmt::format("elements nested deeper than {}; expected a VTK file", kMaxXmlDepth));
      open.push_back(index);
    }
    return false;
  }

  void closeTag(std::vector<int>& open) {
    pos_ += 2;
    const std::string closing = name("an element name after '</'");
    skipSpace();
    if (pos_ >= data_.size() || data_[pos_] != '>')
      fail(fmt::format("expected '>' to end </{}>", excerpt(closing)));
    ++pos_;
    if (open.empty()) fail(fmt::format("</{}> closes no element", excerpt(closing)));
    const XmlElement& top = doc_.elements[open.back()];
    if (top.name != closing)
      fail(fmt::format("</{}> closes {} (line {}); expected </{}>", excerpt(closing), xmlLabel(top),
                       top.line, excerpt(top.name)));
    open.pop_back();
  }

  std::string_view data_;
  const std::string& source_;
  size_t pos_ = 0;
  int line_ = 1;
  XmlDocument doc_;
};

}  // namespace

const std::string* XmlElement::attribute(std::string_view attributeName) const {
  for (const auto& [key, value] : attributes)
    if (key == attributeName) return &value;
  return nullptr;
}

XmlDocument scanXml(std::string_view bytes, const std::string& source) {
  return Scanner(bytes, source).scan();
}

std::string xmlLabel(const XmlElement& element) {
  const std::string* name = element.attribute("Name");
  return name ? fmt::format("<{} Name=\"{}\">", excerpt(element.name), excerpt(*name))
              : fmt::format("<{}>", excerpt(element.name));
}

}  // namespace bcassim::io
