// Closest point on a triangle, with the vertex, edge or face it lies on.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstdint>

namespace d2vdb {

/// The part of a triangle (a, b, c) a closest point lies on. Edge k runs from corner k to corner
/// k + 1 (mod 3), so edge0 = ab, edge1 = bc, edge2 = ca.
enum class TriangleFeature : std::uint8_t { face, edge0, edge1, edge2, vertex0, vertex1, vertex2 };

/// The closest point of the triangle to a query and the feature it lies on.
struct TriangleClosestPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  TriangleFeature feature = TriangleFeature::face;
};

/// Closest point of the triangle (a, b, c) to `p`, found by testing the Voronoi regions of the
/// vertices, then the edges, then the face with barycentric dot products (Ericson, "Real-Time
/// Collision Detection", 2005, section 5.1.5). The feature is the region the tests select, so a
/// point on a region boundary is reported on one of the two adjacent features. Degenerate
/// triangles (collinear or coincident corners) give a closest point on an edge or a vertex, never
/// a division by zero.
inline TriangleClosestPoint closestPointOnTriangle(const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& a,
                                                   const Eigen::Vector3d& b,
                                                   const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, TriangleFeature::vertex0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, TriangleFeature::vertex1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    return {a + (d1 / (d1 - d3)) * ab, TriangleFeature::edge0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, TriangleFeature::vertex2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    return {a + (d2 / (d2 - d6)) * ac, TriangleFeature::edge2};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return {b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), TriangleFeature::edge1};
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) {
    // Only a degenerate (flat) triangle gets here: its closest point lies on one of its sides.
    const auto onSegment = [&p](const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
      const Eigen::Vector3d along = to - from;
      const double length2 = along.squaredNorm();
      const double t = length2 > 0.0 ? std::clamp((p - from).dot(along) / length2, 0.0, 1.0) : 0.0;
      return Eigen::Vector3d(from + t * along);
    };
    TriangleClosestPoint best{onSegment(a, b), TriangleFeature::edge0};
    const Eigen::Vector3d onBc = onSegment(b, c);
    if ((onBc - p).squaredNorm() < (best.point - p).squaredNorm())
      best = {onBc, TriangleFeature::edge1};
    const Eigen::Vector3d onCa = onSegment(c, a);
    if ((onCa - p).squaredNorm() < (best.point - p).squaredNorm())
      best = {onCa, TriangleFeature::edge2};
    return best;
  }
  const double inverse = 1.0 / sum;
  return {a + ab * (vb * inverse) + ac * (vc * inverse), TriangleFeature::face};
}

}  // namespace d2vdb
