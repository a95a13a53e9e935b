// Splitting text mesh files into lines and whitespace-separated tokens, and parsing numbers from
// tokens exactly (std::from_chars: locale-independent, correctly rounded). Internal to the mesh
// module.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace d2vdb::detail {

/// Walks through text one line at a time. Lines end at '\n'; a '\r' before it is dropped, so LF
/// and CRLF files read alike. A final line without a terminator is still a line.
class LineScanner {
 public:
  /// Scans `text`, whose first byte is at byte `startOffset` of line `firstLineNumber` of the file.
  explicit LineScanner(std::string_view text, std::size_t firstLineNumber = 1,
                       std::size_t startOffset = 0);

  /// Moves to the next line and stores it (without terminator) in `line`; false at the end.
  bool next(std::string_view& line);

  /// Number (from 1) of the line last returned by next().
  std::size_t lineNumber() const { return lineNumber_ - 1; }

  /// Byte offset in the file just past the terminator of the line last returned by next().
  std::size_t offset() const { return startOffset_ + position_; }

  /// True when no line is left.
  bool atEnd() const { return position_ >= text_.size(); }

 private:
  std::string_view text_;
  std::size_t position_ = 0;
  std::size_t lineNumber_;
  std::size_t startOffset_;
};

/// True for the bytes TokenReader treats as separators (space, \t, \r, \n, \v, \f).
inline bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

/// Splits one line into tokens separated by spaces, tabs and other ASCII whitespace.
class TokenReader {
 public:
  explicit TokenReader(std::string_view line) : rest_(line) {}

  /// Stores the next token in `token`; false when none is left.
  bool next(std::string_view& token) {
    std::size_t start = 0;
    while (start < rest_.size() && isSpace(rest_[start])) ++start;
    if (start == rest_.size()) {
      rest_ = {};
      return false;
    }
    std::size_t stop = start + 1;
    while (stop < rest_.size() && !isSpace(rest_[stop])) ++stop;
    token = rest_.substr(start, stop - start);
    rest_.remove_prefix(stop);
    return true;
  }

  /// What is left of the line with leading whitespace removed (e.g. an STL solid's name).
  std::string_view rest();

 private:
  std::string_view rest_;
};

/// `text` without a leading UTF-8 byte order mark (some editors write one at the start of OBJ
/// and ASCII STL files).
inline std::string_view withoutByteOrderMark(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? text.substr(3) : text;
}

/// Result of parsing a token as a number.
enum class NumberStatus {
  Ok,          ///< the whole token is a number that fits the type
  NotANumber,  ///< not a number, or trailing characters after one
  OutOfRange   ///< a number, but too large for the type
};

/// Parses a whole token as a float, correctly rounded ("nan" and "inf" parse: check finiteness).
/// A leading '+' is accepted; values too small for a float become zero of the right sign.
NumberStatus parseFloat(std::string_view token, float& value);

/// As parseFloat, for double.
NumberStatus parseDouble(std::string_view token, double& value);

/// Parses a whole token as a decimal integer (leading '+' or '-' accepted).
NumberStatus parseInteger(std::string_view token, std::int64_t& value);

/// Parses a finite float coordinate or throws InputError "<file>, line <n>: ..." saying whether the
/// token is not a number, not finite, or out of float range. `what` names the value in messages
/// (e.g. "x coordinate").
float parseFiniteFloat(std::string_view token, const std::string& fileName, std::size_t lineNumber,
                       const char* what);

}  // namespace d2vdb::detail
