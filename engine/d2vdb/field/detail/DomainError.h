// The error of an exact target asked about a point outside its working domain.
#pragma once

#include <Eigen/Geometry>

#include <string>

namespace d2vdb::detail {

/// Throws InputError "the point (x, y, z) lies D outside the working domain of the WHAT (box
/// (min) to (max))": coordinates with `pointDigits` significant digits, D with 6.
[[noreturn]] void throwOutsideDomain(const Eigen::Vector3d& point,
                                     const Eigen::AlignedBox3d& domain, const std::string& what,
                                     int pointDigits);

}  // namespace d2vdb::detail
