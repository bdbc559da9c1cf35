// Internal to the io module: a line-by-line text reader that counts lines, and the field parsers
// shared by the text formats (Gmsh, OBJ, CSV), so that every parse error names file and line.
#pragma once
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace bcassim::io {

class TextLines {
 public:
  // Throws InputError "<path>: cannot open file" when the file does not exist or is unreadable.
  explicit TextLines(const std::string& path);

  // Advances to the next line (trailing '\r' removed); false at end of file.
  bool next();
  const std::string& line() const { return line_; }
  int lineNumber() const { return lineNumber_; }
  const std::string& path() const { return path_; }

  // Throws InputError "<path>:<line>: <what>".
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string path_;
  std::ifstream in_;
  std::string line_;
  int lineNumber_ = 0;
};

// Fields separated by blanks (spaces, tabs).
std::vector<std::string_view> splitBlanks(std::string_view line);
// Fields separated by commas, each trimmed of surrounding blanks.
std::vector<std::string_view> splitCommas(std::string_view line);
std::string_view trim(std::string_view s);
bool isBlank(std::string_view s);

// Whole-field parses; false when the field is not entirely a number. A parsed double may be
// NaN or infinite: callers decide whether that is allowed.
bool parseDouble(std::string_view field, double& value);
bool parseInt(std::string_view field, long long& value);

// A text from a file as it may be quoted in a one-line message: every byte that is not printable
// ASCII (control characters, escape sequences, line breaks, bytes above 0x7e) written as \xNN, and
// long fields shortened to `maxBytes` bytes and "...". Every reader quotes file text through it.
std::string excerpt(std::string_view field, size_t maxBytes = 40);

}  // namespace bcassim::io
