#include "d2vdb/core/NumberFormat.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <limits>

namespace d2vdb {

std::string formatNumber(double value, int significantDigits) {
  // Room for the longest %g output of a double at the largest precision accepted below.
  constexpr int kMaxDigits = std::numeric_limits<double>::max_digits10 + 3;
  std::array<char, 64> buffer{};
  const std::to_chars_result result =
      significantDigits > 0
          ? std::to_chars(buffer.data(), buffer.data() + buffer.size(), value,
                          std::chars_format::general, std::min(significantDigits, kMaxDigits))
          : std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::string formatPoint(const Eigen::Vector3d& point, int significantDigits, int dimension) {
  std::string text = "(" + formatNumber(point.x(), significantDigits) + ", " +
                     formatNumber(point.y(), significantDigits);
  if (dimension != 2) text += ", " + formatNumber(point.z(), significantDigits);
  return text + ")";
}

std::string quotedPath(const std::filesystem::path& path) {
  return "'" + path.string() + "'";
}

}  // namespace d2vdb
