// Internal to the io module: the blank-separated tokens of a text held in memory, each with the
// line it is on, for the formats whose records are not one per line (PLY's ASCII data, Medit's
// .mesh); '#' comments skipped where the format has them.
#pragma once
#include <cstddef>
#include <string_view>

namespace bcassim::io {

class TextTokens {
 public:
  // `text` must outlive the tokens; `firstLine` is the file line `text` starts on.
  TextTokens(std::string_view text, int firstLine, bool hashComments)
      : text_(text), hashComments_(hashComments), line_(firstLine), tokenLine_(firstLine) {}

  // The next token; empty at the end of the text (line() is then the last line).
  std::string_view next();
  // The line of the token next() returned last.
  int line() const { return tokenLine_; }
  // Bytes not read yet.
  std::size_t left() const { return text_.size() - pos_; }

 private:
  bool isBlank(char c) const;
  bool endsToken(char c) const { return isBlank(c) || (hashComments_ && c == '#'); }

  std::string_view text_;
  bool hashComments_;
  std::size_t pos_ = 0;
  int line_, tokenLine_;
};

}  // namespace bcassim::io
