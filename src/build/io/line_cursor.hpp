// The one way the text readers (molecule.cpp, topology_formats.cpp, text_trajectory.cpp) walk
// a text line by line: from a byte offset on, each line without its "\n" or "\r\n", counted.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string>
#include <string_view>

#include "build/io/text_fields.hpp"

namespace surftrace::build::text {

// Lines of `text` from byte `offset` on, the first numbered `firstLine`. The text must outlive
// the cursor and keep its size (its bytes may be rewritten in place).
class LineCursor {
 public:
  explicit LineCursor(const std::string& text, std::size_t offset = 0, int firstLine = 1)
      : text_(text), pos_(offset), number_(firstLine - 1) {}

  // The next line into `line`; false at the end of the text.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    line_ = pos_;
    const std::size_t end = lineEnd();
    line = std::string_view(text_.data() + pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++number_;
    return true;
  }

  // Skips `count` lines; returns how many there were.
  std::size_t skip(std::size_t count) {
    std::size_t skipped = 0;
    for (; skipped < count && pos_ < text_.size(); ++skipped) {
      line_ = pos_;
      pos_ = lineEnd() + 1;
      ++number_;
    }
    return skipped;
  }

  // Whether nothing but white space is left.
  bool onlySpaceLeft() const {
    for (std::size_t i = pos_; i < text_.size(); ++i)
      if (!isSpace(text_[i])) return false;
    return true;
  }

  std::size_t offset() const { return std::min(pos_, text_.size()); }  // of the next line
  std::size_t lineOffset() const { return line_; }  // of the line last read or skipped
  int number() const { return number_; }            // of the line last read or skipped

 private:
  // Where the line at pos_ ends: its '\n', or the end of the text.
  std::size_t lineEnd() const {
    const void* nl = std::memchr(text_.data() + pos_, '\n', text_.size() - pos_);
    return nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - text_.data()) : text_.size();
  }

  const std::string& text_;
  std::size_t pos_;
  std::size_t line_ = 0;
  int number_;
};

}  // namespace surftrace::build::text
