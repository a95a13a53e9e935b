#include "d2vdb/field/detail/SelfIntersection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

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

/// Whether some axis proves the segment and the triangle farther apart than `margin`: their
/// projections onto it are separated by more than `margin` times its length. The axes tried are
/// those of the separating axis theorem for a segment and a flat triangle (the triangle's normal,
/// its in-plane edge normals, and the segment's direction crossed with each edge), so that a
/// segment clear of the triangle is almost always proved so here, with a few dot products.
/// Projections are taken relative to a corner, so that their rounding is relative to the
/// triangle's size, far below any margin derived from the coordinates' magnitude.
bool provablyApart(const Vector& p0, const Vector& p1, const Corners& t, double margin) {
  const Vector q0 = p0 - t[0];
  const Vector q1 = p1 - t[0];
  const Vector c1 = t[1] - t[0];
  const Vector c2 = t[2] - t[0];
  const auto separates = [&](const Vector& axis) {
    const double s0 = axis.dot(q0);
    const double s1 = axis.dot(q1);
    const double d1 = axis.dot(c1);
    const double d2 = axis.dot(c2);
    const double gap = std::max(std::min(s0, s1) - std::max({0.0, d1, d2}),
                                std::min({0.0, d1, d2}) - std::max(s0, s1));
    return gap > 0.0 && gap * gap > margin * margin * axis.squaredNorm();
  };
  const Vector normal = c1.cross(c2);
  if (separates(normal)) return true;
  const std::array<Vector, 3> edges{c1, t[2] - t[1], -c2};
  for (const Vector& edge : edges) {
    if (separates(normal.cross(edge))) return true;
  }
  const Vector direction = q1 - q0;
  for (const Vector& edge : edges) {
    if (separates(direction.cross(edge))) return true;
  }
  return false;
}

/// Whether the segment comes within `tolerance` of the triangle. Complete: if the segment
/// touches the triangle but does not cross its interior with room to spare, an end lies within
/// `tolerance` of the triangle or the segment passes within it of an edge (the part of the
/// segment near the plane enters the triangle across its boundary).
bool segmentMeetsTriangle(const Vector& p0, const Vector& p1, const Corners& t, double tolerance) {
  // Every way of meeting below puts the segment within `tolerance` of the triangle (up to
  // rounding far below it); twice that separation rules them all out.
  if (provablyApart(p0, p1, t, 2.0 * tolerance)) return false;
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

namespace {

// Calls onPair(t, u) (triangle indices) for every intersecting pair, once, in parallel over the
// BVH's leaves.
template <typename OnPair>
void forEachIntersectingPair(const std::vector<Eigen::Vector3d>& points,
                             const std::vector<TriangleIndices>& triangles,
                             const std::vector<bool>& degenerate, const TriangleBvh& bvh,
                             double tolerance, const OnPair& onPair) {
  const std::vector<TriangleBvh::Node>& nodes = bvh.nodes();
  if (nodes.empty()) return;
  const std::vector<std::uint32_t>& order = bvh.order();
  // Each triangle's box, grown by the tolerance, in leaf order (contiguous for the pair loops).
  struct Box {
    Vector low, high;
  };
  std::vector<Box> boxes(order.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const TriangleIndices& tri = triangles[order[i]];
      const Vector& a = points[tri[0]];
      const Vector& b = points[tri[1]];
      const Vector& c = points[tri[2]];
      boxes[i].low = a.cwiseMin(b).cwiseMin(c) - Vector::Constant(tolerance);
      boxes[i].high = a.cwiseMax(b).cwiseMax(c) + Vector::Constant(tolerance);
    }
  });
  std::vector<std::uint32_t> leaves;
  for (std::uint32_t index = 0; index < nodes.size(); ++index) {
    if (nodes[index].isLeaf()) leaves.push_back(index);
  }
  // Grown boxes that do not overlap hold their triangles more than `tolerance` apart (the
  // growth on one side alone would prove it; both sides keep the test symmetric).
  const auto apart = [](const Vector& low, const Vector& high, const Box& other) {
    return (other.low.array() > high.array()).any() || (other.high.array() < low.array()).any();
  };
  const auto pairIntersects = [&](std::uint32_t i, std::uint32_t j) {
    const std::uint32_t t = order[i];
    const std::uint32_t u = order[j];
    if (degenerate[t] || degenerate[u]) return false;
    if (apart(boxes[i].low, boxes[i].high, boxes[j])) return false;
    return trianglesIntersect(points, triangles[t], triangles[u], tolerance);
  };
  // Leaf against leaf: each leaf meets the leaves (its own included) whose boxes overlap its
  // own, taking each pair of leaves once (from the lower node index). A subtree's nodes occupy a
  // contiguous index range [index, end), so subtrees entirely below the leaf are skipped.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 16), [&](const auto& range) {
    std::array<std::uint32_t, 2> stack[128];
    for (std::size_t n = range.begin(); n != range.end(); ++n) {
      const std::uint32_t self = leaves[n];
      const TriangleBvh::Node& leaf = nodes[self];
      const Vector low = leaf.low - Vector::Constant(tolerance);
      const Vector high = leaf.high + Vector::Constant(tolerance);
      int top = 0;
      stack[top++] = {0, static_cast<std::uint32_t>(nodes.size())};
      while (top > 0) {
        const auto [index, end] = stack[--top];
        if (end <= self) continue;
        const TriangleBvh::Node& node = nodes[index];
        if ((node.low.array() > high.array()).any() || (node.high.array() < low.array()).any())
          continue;
        if (!node.isLeaf()) {
          stack[top++] = {node.right, end};
          stack[top++] = {index + 1, node.right};
          continue;
        }
        for (std::uint32_t i = leaf.begin; i < leaf.end; ++i) {
          for (std::uint32_t j = index == self ? i + 1 : node.begin; j < node.end; ++j) {
            if (pairIntersects(i, j)) onPair(order[i], order[j]);
          }
        }
      }
    }
  });
}

}  // namespace

std::vector<bool> selfIntersectingTriangles(const std::vector<Eigen::Vector3d>& points,
                                            const std::vector<TriangleIndices>& triangles,
                                            const std::vector<bool>& degenerate,
                                            const TriangleBvh& bvh, double tolerance) {
  const auto marks = std::make_unique<std::atomic<bool>[]>(triangles.size());
  forEachIntersectingPair(points, triangles, degenerate, bvh, tolerance,
                          [&marks](std::uint32_t t, std::uint32_t u) {
                            marks[t].store(true, std::memory_order_relaxed);
                            marks[u].store(true, std::memory_order_relaxed);
                          });
  std::vector<bool> intersecting(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) intersecting[t] = marks[t].load();
  return intersecting;
}

}  // namespace d2vdb::detail
