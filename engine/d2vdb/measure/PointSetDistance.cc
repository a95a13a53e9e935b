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
  // The box's longest side over the cube root of a quarter of the points: about four points
  // per cell in a solid cloud, more in flat or thin ones, and never a cell far below the
  // spacing (a flat cloud has no volume to divide).
  const double longest = points_.empty() ? 1.0 : box.sizes().maxCoeff();
  cell_ = longest > 0.0 ? longest / std::max(1.0, std::cbrt(points_.size() / 4.0)) : 1.0;
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3i cell = cellOf(points_[i]);
    grid_[key(cell)].push_back(i);
    lowCell_ = i == 0 ? cell : lowCell_.cwiseMin(cell);
    highCell_ = i == 0 ? cell : highCell_.cwiseMax(cell);
  }
}

double PointSetDistance::operator()(const Eigen::Vector3d& x) const {
  double best = std::numeric_limits<double>::infinity();
  if (points_.empty()) return best;
  // Cells of growing Chebyshev rings around the query's cell, clipped to the occupied cells:
  // the first ring that reaches them, and none after the one that covers them all.
  const Eigen::Vector3i center = cellOf(x);
  const Eigen::Vector3i low = lowCell_ - center, high = highCell_ - center;
  const int first = std::max({0, low.maxCoeff(), -high.minCoeff()});
  const int last = std::max({-low.minCoeff(), high.maxCoeff(), 0});
  for (int ring = first; ring <= last; ++ring) {
    for (int i = std::max(-ring, low.x()); i <= std::min(ring, high.x()); ++i) {
      for (int j = std::max(-ring, low.y()); j <= std::min(ring, high.y()); ++j) {
        for (int k = std::max(-ring, low.z()); k <= std::min(ring, high.z()); ++k) {
          if (std::max({std::abs(i), std::abs(j), std::abs(k)}) != ring) continue;
          const auto found = grid_.find(key(center + Eigen::Vector3i(i, j, k)));
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
