#include "d2vdb/measure/PointSetDistance.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace d2vdb {

PointSetDistance::PointSetDistance(std::vector<Eigen::Vector3d> points)
    : points_(std::move(points)) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : points_) box.extend(p);
  // About four points per cell of a grid over the set's bounding box.
  const double volume = std::max(box.sizes().prod(), 1e-30);
  cell_ = std::max(std::cbrt(volume / std::max<double>(1.0, points_.size() / 4.0)),
                   1e-9 * std::max(box.sizes().maxCoeff(), 1e-300));
  for (std::size_t i = 0; i < points_.size(); ++i) grid_[key(cellOf(points_[i]))].push_back(i);
}

double PointSetDistance::operator()(const Eigen::Vector3d& x) const {
  const Eigen::Vector3i centre = cellOf(x);
  double best = std::numeric_limits<double>::infinity();
  if (points_.empty()) return best;
  for (int ring = 0; ring < 1 << 20; ++ring) {
    for (int i = -ring; i <= ring; ++i) {
      for (int j = -ring; j <= ring; ++j) {
        for (int k = -ring; k <= ring; ++k) {
          if (std::max({std::abs(i), std::abs(j), std::abs(k)}) != ring) continue;
          const auto found = grid_.find(key(centre + Eigen::Vector3i(i, j, k)));
          if (found == grid_.end()) continue;
          for (const std::size_t index : found->second) {
            best = std::min(best, (points_[index] - x).squaredNorm());
          }
        }
      }
    }
    // Every point outside the searched cube is at least `ring` cells away.
    if (best <= std::pow(ring * cell_, 2)) break;
  }
  return std::sqrt(best);
}

Eigen::Vector3i PointSetDistance::cellOf(const Eigen::Vector3d& p) const {
  return (p / cell_).array().floor().cast<int>();
}

std::int64_t PointSetDistance::key(const Eigen::Vector3i& cell) {
  return (static_cast<std::int64_t>(cell.x()) * 73856093) ^
         (static_cast<std::int64_t>(cell.y()) * 19349663) ^
         (static_cast<std::int64_t>(cell.z()) * 83492791);
}

}  // namespace d2vdb
