// Internal: shortest round-trip text of a double, for error messages.
#pragma once

#include <array>
#include <charconv>
#include <string>

namespace d2vdb::detail {

/// The shortest decimal text that reads back as exactly `value` ("0.1", "1e-300", "nan", "inf").
inline std::string formatNumber(double value) {
  std::array<char, 32> buffer{};
  const std::to_chars_result result =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

}  // namespace d2vdb::detail
