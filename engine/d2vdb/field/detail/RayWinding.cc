#include "d2vdb/field/detail/RayWinding.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace d2vdb::detail {
namespace {

/// Shewchuk's bound for the first stage of orient3d, (7 + 56 eps) eps with eps = 2^-53, rounded
/// up generously: |computed - exact| <= kOrientBound * permanent.
constexpr double kOrientBound = 1e-15;

/// Fixed ray directions, none along an axis or a diagonal (scans and voxel grids are full of
/// those), tried in order.
const std::array<Eigen::Vector3d, 6> kDirections{{
    Eigen::Vector3d(0.8273, 0.3151, 0.4650).normalized(),
    Eigen::Vector3d(-0.2718, 0.9129, 0.3046).normalized(),
    Eigen::Vector3d(0.1414, -0.3853, 0.9119).normalized(),
    Eigen::Vector3d(-0.6931, -0.5772, -0.4316).normalized(),
    Eigen::Vector3d(0.5, -0.8660, -0.1732).normalized(),
    Eigen::Vector3d(-0.3010, 0.0467, -0.9524).normalized(),
}};

/// Whether the segment from p to e may meet the box [low, high] (slab test, with a margin that
/// covers rounding: a false "may" only costs time).
bool segmentMayHitBox(const Eigen::Vector3d& p, const Eigen::Vector3d& e,
                      const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  double enter = 0.0, leave = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double margin = 1e-9 * (1.0 + std::abs(low[axis]) + std::abs(high[axis]));
    const double lo = low[axis] - margin, hi = high[axis] + margin;
    const double delta = e[axis] - p[axis];
    if (delta == 0.0) {
      if (p[axis] < lo || p[axis] > hi) return false;
      continue;
    }
    double t0 = (lo - p[axis]) / delta, t1 = (hi - p[axis]) / delta;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0 - 1e-12);
    leave = std::min(leave, t1 + 1e-12);
    if (enter > leave) return false;
  }
  return true;
}

/// The signed crossing of the segment p -> e with triangle (a, b, c): +1 when it leaves through
/// the front (p behind), -1 through the back, 0 when it misses; nothing when a predicate is in
/// doubt and could change that.
std::optional<int> crossing(const Eigen::Vector3d& p, const Eigen::Vector3d& e,
                            const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
  const int sp = certifiedOrientation(a, b, c, p);
  const int se = certifiedOrientation(a, b, c, e);
  if (sp != 0 && sp == se) return 0;  // both ends on one side
  const int s1 = certifiedOrientation(p, e, a, b);
  const int s2 = certifiedOrientation(p, e, b, c);
  const int s3 = certifiedOrientation(p, e, c, a);
  // Certainly outside the triangle's edges: two certain, opposite signs.
  if ((s1 * s2 < 0) || (s2 * s3 < 0) || (s3 * s1 < 0)) return 0;
  if (sp == 0 || se == 0 || s1 == 0 || s2 == 0 || s3 == 0) return std::nullopt;
  return sp > 0 ? 1 : -1;
}

}  // namespace

int certifiedOrientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  const double adx = a.x() - d.x(), ady = a.y() - d.y(), adz = a.z() - d.z();
  const double bdx = b.x() - d.x(), bdy = b.y() - d.y(), bdz = b.z() - d.z();
  const double cdx = c.x() - d.x(), cdy = c.y() - d.y(), cdz = c.z() - d.z();
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                           (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                           (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
  const double bound = kOrientBound * permanent;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return 0;
}

std::optional<long> rayWindingNumber(const TriangleBvh& bvh,
                                     const std::vector<Eigen::Vector3d>& points,
                                     const std::vector<TriangleIndices>& triangles,
                                     const Eigen::Vector3d& q) {
  const std::vector<TriangleBvh::Node>& nodes = bvh.nodes();
  if (nodes.empty()) return 0;
  // Far enough that the segment's end lies outside the root box by more than its size.
  const Eigen::Vector3d& low = nodes[0].low;
  const Eigen::Vector3d& high = nodes[0].high;
  const double reach = 2.0 * ((high - low).norm() + (q - 0.5 * (low + high)).norm()) + 1.0;
  for (const Eigen::Vector3d& direction : kDirections) {
    const Eigen::Vector3d end = q + reach * direction;
    long winding = 0;
    bool certain = true;
    walkDepthFirst(bvh, [&](std::uint32_t, const TriangleBvh::Node& node) {
      if (!segmentMayHitBox(q, end, node.low, node.high)) return BvhStep::kSkip;
      if (!node.isLeaf()) return BvhStep::kChildren;
      for (std::uint32_t i = node.begin; i < node.end; ++i) {
        const auto [a, b, c] = cornersOf(points, triangles[bvh.order()[i]]);
        const std::optional<int> crossed = crossing(q, end, a, b, c);
        if (!crossed) {
          certain = false;
          return BvhStep::kStop;
        }
        winding += *crossed;
      }
      return BvhStep::kSkip;
    });
    if (certain) return winding;
  }
  return std::nullopt;
}

}  // namespace d2vdb::detail
