// Mathematical constants shared by the modules (C++17 has no std::numbers).
#pragma once

namespace d2vdb {

/// pi, rounded to double precision.
inline constexpr double kPi = 3.14159265358979323846;

}  // namespace d2vdb
