// Certified distances from points, and from the convex hulls of point sets, to the triangles of
// one shape, through a bounding-volume hierarchy over them.
#pragma once

#include <Eigen/Core>

#include <limits>
#include <vector>

#include "d2vdb/measure/HausdorffShape.h"
#include "d2vdb/mesh/TriangleBvh.h"

namespace d2vdb::detail {

/// Certified bounds of the distance from a point to the target shape, with its closest point.
struct PointBound {
  double lower = std::numeric_limits<double>::infinity();  ///< <= the exact distance
  double upper = std::numeric_limits<double>::infinity();  ///< >= the exact distance
  Eigen::Vector3d closest = Eigen::Vector3d::Zero();       ///< attains `upper` up to rounding
};

/// Distances to the triangles of a shape, which must outlive this object (a TriangleBvh is built
/// over them). Queries are const, single-threaded each, and may run on any number of threads at
/// once.
class TargetDistance {
 public:
  explicit TargetDistance(const HausdorffShape& to);

  /// Bounds of the distance from `p` to the shape. The lower bound is the smallest lower bound of
  /// the triangles visited: every subtree left unvisited has a box at least as far as the best
  /// upper bound, which is at least the visited triangles' smallest lower bound.
  PointBound point(const Eigen::Vector3d& p) const;

  /// min over the target's triangles t of max over the `count` points of d(point, t): because the
  /// distance to one triangle is convex, an upper bound of the distance to the target over the
  /// convex hull of the points. The walk stops once a value <= `enough` is found and returns it,
  /// and returns `known` when nothing beats it.
  double hullUpper(const Eigen::Vector3d* points, int count, double enough, double known) const;

 private:
  double hullBoxLower(const Eigen::Vector3d* points, int count,
                      const TriangleBvh::Node& node) const;
  double triangleUpper(const Eigen::Vector3d* points, int count, const TriangleIndices& triangle,
                       double stop) const;

  const std::vector<Eigen::Vector3d>& points_;
  const std::vector<TriangleIndices>& triangles_;
  TriangleBvh bvh_;
};

}  // namespace d2vdb::detail
