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
using Point2 = Eigen::Vector2d;

/// Drops the coordinate along which `normal` is largest, for 2D tests within a plane.
struct PlaneProjection {
  int first = 0;
  int second = 1;
  explicit PlaneProjection(const Vector& normal) {
    int axis = 0;
    normal.cwiseAbs().maxCoeff(&axis);
    first = (axis + 1) % 3;
    second = (axis + 2) % 3;
  }
  Point2 operator()(const Vector& p) const { return {p[first], p[second]}; }
};

double cross2(const Point2& a, const Point2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// Signed distance of c from the line through a and b (positive on the left), in the 2D units.
double sideOfLine(const Point2& a, const Point2& b, const Point2& c) {
  const Point2 along = b - a;
  const double length = along.norm();
  return length > 0.0 ? cross2(along, c - a) / length : (c - a).norm();
}

/// Whether the 2D segments meet (touching within `tolerance` counts).
bool segmentsMeet(const Point2& p0, const Point2& p1, const Point2& q0, const Point2& q1,
                  double tolerance) {
  const double d1 = sideOfLine(q0, q1, p0);
  const double d2 = sideOfLine(q0, q1, p1);
  if ((d1 > tolerance && d2 > tolerance) || (d1 < -tolerance && d2 < -tolerance)) return false;
  const double d3 = sideOfLine(p0, p1, q0);
  const double d4 = sideOfLine(p0, p1, q1);
  if ((d3 > tolerance && d4 > tolerance) || (d3 < -tolerance && d4 < -tolerance)) return false;
  const bool collinear = std::abs(d1) <= tolerance && std::abs(d2) <= tolerance &&
                         std::abs(d3) <= tolerance && std::abs(d4) <= tolerance;
  if (!collinear) return true;
  // Collinear: overlap of the projections on the longer segment's direction.
  Point2 direction = (p1 - p0).squaredNorm() >= (q1 - q0).squaredNorm() ? p1 - p0 : q1 - q0;
  const double length = direction.norm();
  if (length == 0.0) return (p0 - q0).norm() <= tolerance;
  direction /= length;
  const auto [pLow, pHigh] = std::minmax(direction.dot(p0), direction.dot(p1));
  const auto [qLow, qHigh] = std::minmax(direction.dot(q0), direction.dot(q1));
  return pLow <= qHigh + tolerance && qLow <= pHigh + tolerance;
}

/// Whether the 2D point lies in the triangle or within `tolerance` of it.
bool pointInTriangle(const Point2& p, const std::array<Point2, 3>& t, double tolerance) {
  const double orientation = cross2(t[1] - t[0], t[2] - t[0]) >= 0.0 ? 1.0 : -1.0;
  for (int k = 0; k < 3; ++k) {
    if (orientation * sideOfLine(t[k], t[(k + 1) % 3], p) < -tolerance) return false;
  }
  return true;
}

/// Two triangles in (nearly) the same plane, compared in 2D.
bool coplanarTrianglesMeet(const std::array<Vector, 3>& a, const std::array<Vector, 3>& b,
                           const Vector& normal, double tolerance) {
  const PlaneProjection project(normal);
  const std::array<Point2, 3> a2{project(a[0]), project(a[1]), project(a[2])};
  const std::array<Point2, 3> b2{project(b[0]), project(b[1]), project(b[2])};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (segmentsMeet(a2[i], a2[(i + 1) % 3], b2[j], b2[(j + 1) % 3], tolerance)) return true;
    }
  }
  return pointInTriangle(a2[0], b2, tolerance) || pointInTriangle(b2[0], a2, tolerance);
}

Vector unitNormal(const std::array<Vector, 3>& t) {
  return (t[1] - t[0]).cross(t[2] - t[0]).normalized();
}

/// Whether the segment [p0, p1] meets the triangle (within `tolerance`).
bool segmentMeetsTriangle(const Vector& p0, const Vector& p1, const std::array<Vector, 3>& t,
                          double tolerance) {
  const Vector normal = unitNormal(t);
  const double d0 = normal.dot(p0 - t[0]);
  const double d1 = normal.dot(p1 - t[0]);
  if ((d0 > tolerance && d1 > tolerance) || (d0 < -tolerance && d1 < -tolerance)) return false;
  if (std::abs(d0) <= tolerance && std::abs(d1) <= tolerance) {
    const PlaneProjection project(normal);
    const std::array<Point2, 3> t2{project(t[0]), project(t[1]), project(t[2])};
    const Point2 q0 = project(p0);
    const Point2 q1 = project(p1);
    if (pointInTriangle(q0, t2, tolerance) || pointInTriangle(q1, t2, tolerance)) return true;
    for (int k = 0; k < 3; ++k) {
      if (segmentsMeet(q0, q1, t2[k], t2[(k + 1) % 3], tolerance)) return true;
    }
    return false;
  }
  Vector crossing;
  if (std::abs(d0) <= tolerance) {
    crossing = p0;
  } else if (std::abs(d1) <= tolerance) {
    crossing = p1;
  } else {
    crossing = p0 + (p1 - p0) * (d0 / (d0 - d1));
  }
  for (int k = 0; k < 3; ++k) {
    const Vector edge = t[(k + 1) % 3] - t[k];
    const double inside = normal.dot(edge.cross(crossing - t[k])) / edge.norm();
    if (inside < -tolerance) return false;
  }
  return true;
}

/// The points of triangle t (signed distances `d` to the other plane) that lie on that plane,
/// projected on `direction`: the interval they span (empty: low > high).
std::pair<double, double> intervalOnLine(const std::array<Vector, 3>& t,
                                         const std::array<double, 3>& d, const Vector& direction,
                                         double tolerance) {
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  const auto include = [&](const Vector& p) {
    const double s = direction.dot(p);
    low = std::min(low, s);
    high = std::max(high, s);
  };
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (std::abs(d[i]) <= tolerance) include(t[i]);
    if ((d[i] > tolerance && d[j] < -tolerance) || (d[i] < -tolerance && d[j] > tolerance)) {
      include(t[i] + (t[j] - t[i]) * (d[i] / (d[i] - d[j])));
    }
  }
  return {low, high};
}

/// Triangles without a shared corner.
bool disjointTrianglesMeet(const std::array<Vector, 3>& a, const std::array<Vector, 3>& b,
                           double tolerance) {
  const Vector na = unitNormal(a);
  const std::array<double, 3> db{na.dot(b[0] - a[0]), na.dot(b[1] - a[0]), na.dot(b[2] - a[0])};
  const auto allBeyond = [tolerance](const std::array<double, 3>& d) {
    return (d[0] > tolerance && d[1] > tolerance && d[2] > tolerance) ||
           (d[0] < -tolerance && d[1] < -tolerance && d[2] < -tolerance);
  };
  const auto allOn = [tolerance](const std::array<double, 3>& d) {
    return std::abs(d[0]) <= tolerance && std::abs(d[1]) <= tolerance &&
           std::abs(d[2]) <= tolerance;
  };
  if (allBeyond(db)) return false;
  const Vector nb = unitNormal(b);
  const std::array<double, 3> da{nb.dot(a[0] - b[0]), nb.dot(a[1] - b[0]), nb.dot(a[2] - b[0])};
  if (allBeyond(da)) return false;
  Vector direction = na.cross(nb);
  if (allOn(da) || allOn(db) || direction.norm() < 1e-12) {
    return coplanarTrianglesMeet(a, b, na, tolerance);
  }
  direction.normalize();
  const auto [aLow, aHigh] = intervalOnLine(a, da, direction, tolerance);
  const auto [bLow, bHigh] = intervalOnLine(b, db, direction, tolerance);
  if (aLow > aHigh || bLow > bHigh) return false;
  return aLow <= bHigh + tolerance && bLow <= aHigh + tolerance;
}

/// Whether x lies in the plane of the sector at v between rays v->a and v->b (normal n, the
/// sector's right-hand normal) and inside the sector (its rays included, within tolerance).
bool inSector(const Vector& x, const Vector& v, const Vector& a, const Vector& b,
              const Vector& normal, double tolerance) {
  if (std::abs(normal.dot(x - v)) > tolerance) return false;
  const Vector u = x - v;
  const Vector va = a - v;
  const Vector vb = b - v;
  return normal.dot(va.cross(u)) / va.norm() >= -tolerance &&
         normal.dot(u.cross(vb)) / vb.norm() >= -tolerance && u.norm() > tolerance;
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
  const std::array<Vector, 3> pa{points[a[0]], points[a[1]], points[a[2]]};
  const std::array<Vector, 3> pb{points[b[0]], points[b[1]], points[b[2]]};
  switch (shared) {
    case 0:
      return disjointTrianglesMeet(pa, pb, tolerance);
    case 1: {
      // Corner 0 shared: they meet elsewhere only if an opposite edge crosses the other triangle
      // or an edge from the shared corner runs into the other's angle within its plane.
      if (segmentMeetsTriangle(pb[1], pb[2], pa, tolerance)) return true;
      if (segmentMeetsTriangle(pa[1], pa[2], pb, tolerance)) return true;
      const Vector na = unitNormal(pa);
      const Vector nb = unitNormal(pb);
      return inSector(pb[1], pa[0], pa[1], pa[2], na, tolerance) ||
             inSector(pb[2], pa[0], pa[1], pa[2], na, tolerance) ||
             inSector(pa[1], pb[0], pb[1], pb[2], nb, tolerance) ||
             inSector(pa[2], pb[0], pb[1], pb[2], nb, tolerance);
    }
    case 2: {
      // Edge shared: they meet elsewhere only when folded flat onto each other.
      const Vector na = unitNormal(pa);
      if (std::abs(na.dot(pb[2] - pa[0])) > tolerance) return false;
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
