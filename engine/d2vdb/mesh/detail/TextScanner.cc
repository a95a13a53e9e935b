#include "d2vdb/mesh/detail/TextScanner.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <system_error>

#include "d2vdb/mesh/detail/MeshFileCommon.h"

namespace d2vdb::detail {
namespace {

/// The token without a leading '+' that is followed by a digit or a decimal point (from_chars
/// rejects '+', text mesh files sometimes contain it).
std::string_view withoutPlus(std::string_view token) {
  if (token.size() >= 2 && token[0] == '+' &&
      ((token[1] >= '0' && token[1] <= '9') || token[1] == '.')) {
    return token.substr(1);
  }
  return token;
}

/// For a token that std::from_chars found out of range: true when it underflows (a negative
/// decimal exponent), so that the value is a signed zero; false when it overflows.
bool underflows(std::string_view token) {
  const std::size_t exponent = token.find_first_of("eE");
  if (exponent == std::string_view::npos || exponent + 1 >= token.size()) return false;
  return token[exponent + 1] == '-';
}

template <typename Real>
NumberStatus parseReal(std::string_view token, Real& value) {
  const std::string_view digits = withoutPlus(token);
  if (digits.empty()) return NumberStatus::NotANumber;
  const char* const end = digits.data() + digits.size();
  Real parsed = 0;
  const std::from_chars_result result =
      std::from_chars(digits.data(), end, parsed, std::chars_format::general);
  if (result.ptr != end) return NumberStatus::NotANumber;
  if (result.ec == std::errc::result_out_of_range) {
    if (!underflows(digits)) return NumberStatus::OutOfRange;
    value = digits.front() == '-' ? -Real(0) : Real(0);
    return NumberStatus::Ok;
  }
  if (result.ec != std::errc()) return NumberStatus::NotANumber;
  value = parsed;
  return NumberStatus::Ok;
}

}  // namespace

LineScanner::LineScanner(std::string_view text, std::size_t firstLineNumber,
                         std::size_t startOffset)
    : text_(text), lineNumber_(firstLineNumber), startOffset_(startOffset) {}

bool LineScanner::next(std::string_view& line) {
  if (position_ >= text_.size()) return false;
  const char* const begin = text_.data() + position_;
  const std::size_t remaining = text_.size() - position_;
  const void* const newline = std::memchr(begin, '\n', remaining);
  std::size_t length = remaining;
  std::size_t consumed = remaining;
  if (newline != nullptr) {
    length = static_cast<std::size_t>(static_cast<const char*>(newline) - begin);
    consumed = length + 1;
  }
  if (length > 0 && begin[length - 1] == '\r') --length;
  line = std::string_view(begin, length);
  position_ += consumed;
  ++lineNumber_;
  return true;
}

std::string_view TokenReader::rest() {
  while (!rest_.empty() && isSpace(rest_.front())) rest_.remove_prefix(1);
  return rest_;
}

NumberStatus parseFloat(std::string_view token, float& value) {
  return parseReal(token, value);
}

NumberStatus parseDouble(std::string_view token, double& value) {
  return parseReal(token, value);
}

NumberStatus parseInteger(std::string_view token, std::int64_t& value) {
  const std::string_view digits = withoutPlus(token);
  if (digits.empty()) return NumberStatus::NotANumber;
  const char* const end = digits.data() + digits.size();
  std::int64_t parsed = 0;
  const std::from_chars_result result = std::from_chars(digits.data(), end, parsed);
  if (result.ptr != end) return NumberStatus::NotANumber;
  if (result.ec == std::errc::result_out_of_range) return NumberStatus::OutOfRange;
  if (result.ec != std::errc()) return NumberStatus::NotANumber;
  value = parsed;
  return NumberStatus::Ok;
}

float parseFiniteFloat(std::string_view token, const std::string& fileName, std::size_t lineNumber,
                       const char* what) {
  float value = 0.0f;
  switch (parseFloat(token, value)) {
    case NumberStatus::Ok:
      break;
    case NumberStatus::NotANumber:
      throwAtLine(fileName, lineNumber,
                  std::string(what) + " " + inQuotes(token) + " is not a number");
    case NumberStatus::OutOfRange:
      throwAtLine(
          fileName, lineNumber,
          std::string(what) + " " + inQuotes(token) + " is out of range for a 32-bit float");
  }
  if (!std::isfinite(value)) {
    throwAtLine(fileName, lineNumber, std::string(what) + " " + inQuotes(token) + " is not finite");
  }
  return value;
}

}  // namespace d2vdb::detail
