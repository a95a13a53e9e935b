#include "d2vdb/measure/detail/TargetDistance.h"

#include <algorithm>

#include "d2vdb/measure/detail/CertifiedDistance.h"

namespace d2vdb::detail {

TargetDistance::TargetDistance(const HausdorffShape& to)
    : points_(to.points), triangles_(to.triangles), bvh_(points_, triangles_) {}

PointBound TargetDistance::point(const Eigen::Vector3d& p) const {
  PointBound result;
  walkDepthFirst(bvh_, [&](std::uint32_t index, const TriangleBvh::Node& node) {
    if (boxDistanceLower(p, node.low, node.high) >= result.upper) return BvhStep::kSkip;
    if (node.isLeaf()) {
      for (std::uint32_t k = node.begin; k < node.end; ++k) {
        const TriangleIndices& triangle = triangles_[bvh_.order()[k]];
        const CertifiedDistance bounds = triangleDistanceBounds(
            p, points_[triangle[0]], points_[triangle[1]], points_[triangle[2]]);
        if (bounds.upper < result.upper) {
          result.upper = bounds.upper;
          result.closest = bounds.closest;
        }
        result.lower = std::min(result.lower, bounds.lower);
      }
      return BvhStep::kSkip;
    }
    const TriangleBvh::Node& left = bvh_.nodes()[index + 1];
    const TriangleBvh::Node& right = bvh_.nodes()[node.right];
    return boxDistanceLower(p, right.low, right.high) < boxDistanceLower(p, left.low, left.high)
               ? BvhStep::kChildrenRightFirst
               : BvhStep::kChildren;
  });
  return result;
}

double TargetDistance::hullUpper(const Eigen::Vector3d* points, int count, double enough,
                                 double known) const {
  double best = known;
  walkDepthFirst(bvh_, [&](std::uint32_t index, const TriangleBvh::Node& node) {
    if (hullBoxLower(points, count, node) >= best) return BvhStep::kSkip;
    if (node.isLeaf()) {
      for (std::uint32_t k = node.begin; k < node.end; ++k) {
        best = std::min(best, triangleUpper(points, count, triangles_[bvh_.order()[k]], best));
      }
      return best <= enough ? BvhStep::kStop : BvhStep::kSkip;
    }
    const TriangleBvh::Node& left = bvh_.nodes()[index + 1];
    const TriangleBvh::Node& right = bvh_.nodes()[node.right];
    return hullBoxLower(points, count, right) < hullBoxLower(points, count, left)
               ? BvhStep::kChildrenRightFirst
               : BvhStep::kChildren;
  });
  return best;
}

// max over the points of their distance to the box: a lower bound of max over the points of the
// distance to any triangle in it.
double TargetDistance::hullBoxLower(const Eigen::Vector3d* points, int count,
                                    const TriangleBvh::Node& node) const {
  double largest = 0.0;
  for (int k = 0; k < count; ++k) {
    largest = std::max(largest, boxDistanceLower(points[k], node.low, node.high));
  }
  return largest;
}

// max over the points of the distance upper bound to one triangle, abandoned (returning a value
// >= `stop`) as soon as one point reaches `stop`.
double TargetDistance::triangleUpper(const Eigen::Vector3d* points, int count,
                                     const TriangleIndices& triangle, double stop) const {
  double largest = 0.0;
  for (int k = 0; k < count; ++k) {
    largest = std::max(largest, triangleDistanceUpper(points[k], points_[triangle[0]],
                                                      points_[triangle[1]], points_[triangle[2]]));
    if (largest >= stop) break;
  }
  return largest;
}

}  // namespace d2vdb::detail
