// The exact distance from any point to the nearest of a set of points, through a uniform hash
// grid: what a fit reports as its error against a point cloud.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace d2vdb {

/// Nearest-point distances to a fixed set of points (world units). The search grows ring by ring
/// of grid cells around the query until no closer point can exist, so the answer is exact. The
/// points are copied; the object is immutable after construction and safe to query from many
/// threads. An empty set answers +inf.
class PointSetDistance {
 public:
  explicit PointSetDistance(std::vector<Eigen::Vector3d> points);

  /// The distance from `x` to the nearest point of the set.
  double operator()(const Eigen::Vector3d& x) const;

 private:
  Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const;
  static std::int64_t key(const Eigen::Vector3i& cell);

  std::vector<Eigen::Vector3d> points_;
  double cell_ = 1.0;                                        ///< grid cell side, world units
  Eigen::Vector3i lowCell_{0, 0, 0}, highCell_{-1, -1, -1};  ///< the cells holding points
  std::unordered_map<std::int64_t, std::vector<std::size_t>> grid_;
};

}  // namespace d2vdb
