#include "bcassim/io/TextTokens.h"

#include <cctype>

namespace bcassim::io {

bool TextTokens::isBlank(char c) const { return std::isspace(static_cast<unsigned char>(c)) != 0; }

std::string_view TextTokens::next() {
  for (;;) {
    while (pos_ < text_.size() && isBlank(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (!hashComments_ || pos_ >= text_.size() || text_[pos_] != '#') break;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  const std::size_t start = pos_;
  while (pos_ < text_.size() && !endsToken(text_[pos_])) ++pos_;
  tokenLine_ = line_;
  return text_.substr(start, pos_ - start);
}

}  // namespace bcassim::io
