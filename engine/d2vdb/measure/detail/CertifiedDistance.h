// Distances from a point to a triangle and to a box that are certified against floating-point
// rounding: each lower bound is <= the exact distance and each upper bound >= it, for the exact
// input coordinates (IEEE double, round to nearest). Used by the certified Hausdorff bracket.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace d2vdb::detail {

/// The unit roundoff of IEEE double precision, 2^-53.
constexpr double kUnitRoundoff = 0x1p-53;

/// Barycentric coordinates (beta, gamma) of a point a + beta (b - a) + gamma (c - a) of a triangle.
struct TriangleCoordinates {
  double beta = 0.0;
  double gamma = 0.0;
};

/// The coordinates of the closest point of the triangle (a, b, c) to `p`, by the Voronoi-region
/// tests of Ericson ("Real-Time Collision Detection", 2005, section 5.1.5), then clamped so that
/// beta, gamma >= 0 and beta + gamma <= 1 + u hold for the returned values whatever the rounding
/// did. Degenerate triangles get the closest point on one of their sides.
TriangleCoordinates closestTriangleCoordinates(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                               const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// Certified bounds of the distance from a point to a triangle, with the computed closest point.
struct CertifiedDistance {
  double lower = 0.0;                                 ///< <= the exact distance, >= 0
  double upper = 0.0;                                 ///< >= the exact distance
  Eigen::Vector3d closest = Eigen::Vector3d::Zero();  ///< within rounding of the closest point
};

/// The largest of |x|, |y|, |z|.
inline double largestMagnitude(const Eigen::Vector3d& v) {
  return v.cwiseAbs().maxCoeff();
}

/// An upper bound of the exact distance from `p` to the point `q` = a + beta (b - a) + gamma
/// (c - a) of the triangle, given its computed value `computed`: the construction of q from the
/// coordinates is off by at most 4u (|a| + |b - a| + |c - a|) <= 20u s per coordinate (s the
/// largest coordinate magnitude of the corners), so by 35u s as a vector; clamping lets the
/// coordinates' sum exceed 1 by u, which moves q off the triangle by at most 3.5u s; the norm of
/// p - q is off by at most 4u of itself. The bound adds 48u s and 8u of the distance.
inline double roundedUpDistance(double computed, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c) {
  const double scale = std::max({largestMagnitude(a), largestMagnitude(b), largestMagnitude(c)});
  return computed * (1.0 + 8.0 * kUnitRoundoff) + 48.0 * kUnitRoundoff * scale +
         0x1p-1000;  // the last term covers underflow of squares of tiny distances
}

/// Certified upper bound of the distance from `p` to the triangle (a, b, c), with the point it
/// is attained at (a point of the triangle up to the rounding the bound accounts for).
inline double triangleDistanceUpper(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                    Eigen::Vector3d* closest = nullptr) {
  const TriangleCoordinates coordinates = closestTriangleCoordinates(p, a, b, c);
  const Eigen::Vector3d q = a + coordinates.beta * (b - a) + coordinates.gamma * (c - a);
  if (closest != nullptr) *closest = q;
  return roundedUpDistance((p - q).norm(), a, b, c);
}

/// Certified bounds of the distance from `p` to the triangle (a, b, c).
///
/// Upper: the distance to a point of the triangle given by clamped barycentric coordinates,
/// rounded up (roundedUpDistance()). Lower: for any unit vector m, every point x of the triangle
/// has |p - x| >= m . (p - x) >= min over the corners k of m . (p - c_k), because a linear
/// function takes its minimum over a triangle at a corner. With m along p - q (q the computed
/// closest point) this is the exact distance up to rounding; the dot products and the
/// normalisation are each off by at most 5u |p - c_k| and 3u of themselves, which the bound
/// subtracts (as 16u max_k |p - c_k| and a factor 1 - 8u).
inline CertifiedDistance triangleDistanceBounds(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                                const Eigen::Vector3d& b,
                                                const Eigen::Vector3d& c) {
  CertifiedDistance result;
  result.upper = triangleDistanceUpper(p, a, b, c, &result.closest);
  const Eigen::Vector3d direction = p - result.closest;
  const double length = direction.norm();
  if (!(length > 0.0)) return result;  // lower stays 0
  const Eigen::Vector3d toA = p - a;
  const Eigen::Vector3d toB = p - b;
  const Eigen::Vector3d toC = p - c;
  const double nearest =
      std::min({direction.dot(toA), direction.dot(toB), direction.dot(toC)}) / length;
  const double farthestCorner = std::max({toA.norm(), toB.norm(), toC.norm()});
  const double lower =
      nearest * (1.0 - 8.0 * kUnitRoundoff) - 16.0 * kUnitRoundoff * farthestCorner;
  result.lower = std::clamp(lower, 0.0, result.upper);
  return result;
}

/// Certified lower bound of the distance from `p` to the box [low, high] (0 inside it): each
/// coordinate gap is one rounded subtraction (relative error u) and the norm adds 3u.
inline double boxDistanceLower(const Eigen::Vector3d& p, const Eigen::Vector3d& low,
                               const Eigen::Vector3d& high) {
  double sum = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double gap = std::max({low[axis] - p[axis], 0.0, p[axis] - high[axis]});
    sum += gap * gap;
  }
  return std::sqrt(sum) * (1.0 - 8.0 * kUnitRoundoff);
}

}  // namespace d2vdb::detail
