#include "d2vdb/field/detail/SelfIntersection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

namespace d2vdb::detail {
namespace {

using Vector = Eigen::Vector3d;
using Corners = std::array<Vector, 3>;

/// Distance between the segments [p0, p1] and [q0, q1] (closest points by clamping the line
/// parameters, parallel segments included; Ericson, "Real-Time Collision Detection", 5.1.9).
double segmentDistance(const Vector& p0, const Vector& p1, const Vector& q0, const Vector& q1) {
  const Vector d1 = p1 - p0;
  const Vector d2 = q1 - q0;
  const Vector r = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  double s = 0.0;
  double t = 0.0;
  if (a == 0.0 && e == 0.0) return r.norm();
  if (a == 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e == 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denominator = a * e - b * b;
      s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

double pointTriangleDistance(const Vector& p, const Corners& t) {
  return (closestPointOnTriangle(p, t[0], t[1], t[2]).point - p).norm();
}

/// Whether the segment passes through the triangle's interior with room to spare: its ends on
/// opposite sides of the plane, and the crossing more than `tolerance` inside every edge.
bool crossesInterior(const Vector& p0, const Vector& p1, const Corners& t, double tolerance) {
  const Vector normal = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
  const double d0 = normal.dot(p0 - t[0]);
  const double d1 = normal.dot(p1 - t[0]);
  if (!((d0 > tolerance && d1 < -tolerance) || (d0 < -tolerance && d1 > tolerance))) return false;
  const Vector crossing = p0 + (p1 - p0) * (d0 / (d0 - d1));
  for (int k = 0; k < 3; ++k) {
    const Vector edge = t[(k + 1) % 3] - t[k];
    if (!(normal.dot(edge.cross(crossing - t[k])) / edge.norm() > tolerance)) return false;
  }
  return true;
}

/// Whether the segment comes within `tolerance` of the triangle. Complete: if the segment
/// touches the triangle but does not cross its interior with room to spare, an end lies within
/// `tolerance` of the triangle or the segment passes within it of an edge (the part of the
/// segment near the plane enters the triangle across its boundary).
bool segmentMeetsTriangle(const Vector& p0, const Vector& p1, const Corners& t, double tolerance) {
  if (crossesInterior(p0, p1, t, tolerance)) return true;
  if (pointTriangleDistance(p0, t) <= tolerance || pointTriangleDistance(p1, t) <= tolerance) {
    return true;
  }
  for (int k = 0; k < 3; ++k) {
    if (segmentDistance(p0, p1, t[k], t[(k + 1) % 3]) <= tolerance) return true;
  }
  return false;
}

/// Whether all corners of `t` lie farther than `tolerance` on one side of the plane of `u`.
bool beyondPlane(const Corners& t, const Corners& u, double tolerance) {
  const Vector normal = (u[1] - u[0]).cross(u[2] - u[0]).normalized();
  const double d0 = normal.dot(t[0] - u[0]);
  const double d1 = normal.dot(t[1] - u[0]);
  const double d2 = normal.dot(t[2] - u[0]);
  return (d0 > tolerance && d1 > tolerance && d2 > tolerance) ||
         (d0 < -tolerance && d1 < -tolerance && d2 < -tolerance);
}

}  // namespace

bool trianglesIntersect(const std::vector<Eigen::Vector3d>& points, const TriangleIndices& first,
                        const TriangleIndices& second, double tolerance) {
  // Shared corners: rotate both so that shared ones come first, in the same order.
  std::array<std::uint32_t, 3> a = first;
  std::array<std::uint32_t, 3> b = second;
  int shared = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = shared; j < 3; ++j) {
      if (a[i] == b[j]) {
        std::swap(a[i], a[shared]);
        std::swap(b[j], b[shared]);
        ++shared;
        break;
      }
    }
  }
  const Corners pa{points[a[0]], points[a[1]], points[a[2]]};
  const Corners pb{points[b[0]], points[b[1]], points[b[2]]};
  switch (shared) {
    case 0:
      // Two triangles that meet do so where an edge of one meets the other.
      if (beyondPlane(pb, pa, tolerance) || beyondPlane(pa, pb, tolerance)) return false;
      for (int k = 0; k < 3; ++k) {
        if (segmentMeetsTriangle(pa[k], pa[(k + 1) % 3], pb, tolerance)) return true;
        if (segmentMeetsTriangle(pb[k], pb[(k + 1) % 3], pa, tolerance)) return true;
      }
      return false;
    case 1:
      // Corner 0 shared: beyond it, the triangles can only meet where the edge opposite the
      // shared corner of one meets the other (their intersection is convex and contains the
      // corner; where it ends, it leaves one of them across an edge, and an edge through the
      // corner would have to run inside the other, which puts its far end or the other's
      // opposite edge on it).
      return segmentMeetsTriangle(pb[1], pb[2], pa, tolerance) ||
             segmentMeetsTriangle(pa[1], pa[2], pb, tolerance);
    case 2: {
      // Edge shared: they meet elsewhere only when folded flat onto each other.
      const Vector normal = (pa[1] - pa[0]).cross(pa[2] - pa[0]).normalized();
      if (std::abs(normal.dot(pb[2] - pa[0])) > tolerance) return false;
      const Vector edge = pa[1] - pa[0];
      return edge.cross(pa[2] - pa[0]).dot(edge.cross(pb[2] - pa[0])) > 0.0;
    }
    default:
      return true;  // the same three corners
  }
}

bool hasSelfIntersection(const std::vector<Eigen::Vector3d>& points,
                         const std::vector<TriangleIndices>& triangles,
                         const std::vector<bool>& degenerate, const TriangleBvh& bvh,
                         double tolerance) {
  if (bvh.nodes().empty()) return false;
  std::atomic<bool> found{false};
  const std::vector<TriangleBvh::Node>& nodes = bvh.nodes();
  tbb::parallel_for(
      tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(triangles.size()), 256),
      [&](const tbb::blocked_range<std::uint32_t>& range) {
        std::uint32_t stack[128];
        for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
          if (found.load(std::memory_order_relaxed)) return;
          if (degenerate[t]) continue;
          const TriangleIndices& tri = triangles[t];
          const Vector low = points[tri[0]].cwiseMin(points[tri[1]]).cwiseMin(points[tri[2]]) -
                             Vector::Constant(tolerance);
          const Vector high = points[tri[0]].cwiseMax(points[tri[1]]).cwiseMax(points[tri[2]]) +
                              Vector::Constant(tolerance);
          int top = 0;
          stack[top++] = 0;
          while (top > 0) {
            const std::uint32_t index = stack[--top];
            const TriangleBvh::Node& node = nodes[index];
            if ((node.low.array() > high.array()).any() || (node.high.array() < low.array()).any())
              continue;
            if (!node.isLeaf()) {
              stack[top++] = node.right;
              stack[top++] = index + 1;
              continue;
            }
            for (std::uint32_t i = node.begin; i < node.end; ++i) {
              const std::uint32_t other = bvh.order()[i];
              if (other <= t || degenerate[other]) continue;
              if (trianglesIntersect(points, tri, triangles[other], tolerance)) {
                found.store(true, std::memory_order_relaxed);
                return;
              }
            }
          }
        }
      });
  return found.load();
}

}  // namespace d2vdb::detail
