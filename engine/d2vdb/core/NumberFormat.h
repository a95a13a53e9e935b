// Numbers, points and file names as text for messages and reports, the same way everywhere.
#pragma once

#include <Eigen/Core>

#include <filesystem>
#include <string>

namespace d2vdb {

/// `value` as decimal text, independent of the locale. With `significantDigits` > 0 it is
/// printf's "%.<significantDigits>g" (what a std::ostream prints at that precision: "0.1",
/// "1.5e+08"); with 0 (the default) the shortest text that reads back as exactly `value` ("0.1",
/// "0.30000000000000004", "1e-300"). At most 20 significant digits are printed (a double carries
/// 17). Non-finite values give "nan", "-nan", "inf" or "-inf".
/// Never throws (beyond std::bad_alloc).
std::string formatNumber(double value, int significantDigits = 0);

/// "(x, y, z)", or "(x, y)" when `dimension` is 2, each coordinate as formatNumber(coordinate,
/// significantDigits).
std::string formatPoint(const Eigen::Vector3d& point, int significantDigits = 0, int dimension = 3);

/// A file name as messages quote it: 'name'.
std::string quotedPath(const std::filesystem::path& path);

}  // namespace d2vdb
