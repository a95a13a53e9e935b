#include "d2vdb/measure/MeshHausdorff.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/measure/detail/CertifiedDistance.h"

namespace d2vdb {
namespace {

using detail::boxDistanceLower;
using detail::kUnitRoundoff;
using detail::triangleDistanceBounds;
using detail::triangleDistanceUpper;

constexpr double kNoBound = std::numeric_limits<double>::infinity();

/// Certified bounds of the distance from a point to the target shape, with its closest point.
struct PointBound {
  double lower = kNoBound;
  double upper = kNoBound;
  Eigen::Vector3d closest = Eigen::Vector3d::Zero();
};

/// Certified distances to the triangles of one shape, through a TriangleBvh over them. Queries
/// are const, single-threaded each, and may run on any number of threads.
class TargetDistance {
 public:
  explicit TargetDistance(const HausdorffShape& to)
      : points_(to.points), triangles_(to.triangles), bvh_(points_, triangles_) {}

  /// Bounds of the distance from `p` to the shape. The lower bound is the smallest lower bound of
  /// the triangles visited: every subtree left unvisited has a box at least as far as the best
  /// upper bound, which is at least the visited triangles' smallest lower bound.
  PointBound point(const Eigen::Vector3d& p) const {
    PointBound result;
    walkDepthFirst(bvh_, [&](std::uint32_t index, const TriangleBvh::Node& node) {
      if (boxDistanceLower(p, node.low, node.high) >= result.upper) return BvhStep::kSkip;
      if (node.isLeaf()) {
        for (std::uint32_t k = node.begin; k < node.end; ++k) {
          const TriangleIndices& triangle = triangles_[bvh_.order()[k]];
          const detail::CertifiedDistance bounds = triangleDistanceBounds(
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

  /// min over the target's triangles t of max over `corners` of d(corner, t), an upper bound of
  /// the distance to the target over the convex hull of the corners; the walk stops once a value
  /// <= `enough` is found and returns it, and returns `known` when nothing beats it.
  double hullUpper(const std::array<Eigen::Vector3d, 3>& corners, double enough,
                   double known) const {
    double best = known;
    walkDepthFirst(bvh_, [&](std::uint32_t index, const TriangleBvh::Node& node) {
      if (hullBoxLower(corners, node) >= best) return BvhStep::kSkip;
      if (node.isLeaf()) {
        for (std::uint32_t k = node.begin; k < node.end; ++k) {
          const double value = triangleUpper(corners, triangles_[bvh_.order()[k]], best);
          if (value < best) best = value;
        }
        return best <= enough ? BvhStep::kStop : BvhStep::kSkip;
      }
      const TriangleBvh::Node& left = bvh_.nodes()[index + 1];
      const TriangleBvh::Node& right = bvh_.nodes()[node.right];
      return hullBoxLower(corners, right) < hullBoxLower(corners, left)
                 ? BvhStep::kChildrenRightFirst
                 : BvhStep::kChildren;
    });
    return best;
  }

 private:
  static double hullBoxLower(const std::array<Eigen::Vector3d, 3>& corners,
                             const TriangleBvh::Node& node) {
    return std::max({boxDistanceLower(corners[0], node.low, node.high),
                     boxDistanceLower(corners[1], node.low, node.high),
                     boxDistanceLower(corners[2], node.low, node.high)});
  }

  // max over the corners of the distance upper bound to one triangle, abandoned (returning a
  // value >= `stop`) as soon as one corner reaches `stop`.
  double triangleUpper(const std::array<Eigen::Vector3d, 3>& corners,
                       const TriangleIndices& triangle, double stop) const {
    double largest = 0.0;
    for (const Eigen::Vector3d& corner : corners) {
      largest =
          std::max(largest, triangleDistanceUpper(corner, points_[triangle[0]],
                                                  points_[triangle[1]], points_[triangle[2]]));
      if (largest >= stop) break;
    }
    return largest;
  }

  std::vector<Eigen::Vector3d> points_;
  std::vector<TriangleIndices> triangles_;
  TriangleBvh bvh_;
};

/// A piece of a primitive of the `from` shape: a triangle, a segment (corner 2 = corner 1) or a
/// point (all corners equal), with certified upper bounds of its corners' distances.
struct Piece {
  std::array<Eigen::Vector3d, 3> corners;
  std::array<double, 3> cornerUpper{};
  std::uint8_t cornerCount = 3;  ///< 1 point, 2 segment, 3 triangle
  std::uint8_t depth = 0;
};

/// The best lower bound so far and where it is attained.
struct Witness {
  double lower = -kNoBound;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d closest = Eigen::Vector3d::Zero();

  void offer(double value, const Eigen::Vector3d& at, const Eigen::Vector3d& nearest) {
    if (value > lower) *this = {value, at, nearest};
  }
};

/// The Lipschitz bound of a piece: min over corners k of d(corner k) + the largest distance from
/// corner k to a point of the piece (a corner, by convexity of the norm), rounded up.
double lipschitzUpper(const Piece& piece) {
  double best = kNoBound;
  for (int k = 0; k < piece.cornerCount; ++k) {
    double extent = 0.0;
    for (int j = 0; j < piece.cornerCount; ++j) {
      extent = std::max(extent, (piece.corners[j] - piece.corners[k]).norm());
    }
    best = std::min(best, (piece.cornerUpper[k] + extent) * (1.0 + 8.0 * kUnitRoundoff));
  }
  return best;
}

/// The primitive as a piece: points and segments recognised by equal corners.
Piece initialPiece(const HausdorffShape& from, const TriangleIndices& triangle,
                   const std::vector<double>& pointUpper) {
  std::array<std::uint32_t, 3> corners = {triangle[0], triangle[1], triangle[2]};
  const auto same = [&](std::uint32_t i, std::uint32_t j) {
    return from.points[i] == from.points[j];
  };
  Piece piece;
  if (same(corners[0], corners[1]) && same(corners[1], corners[2])) {
    piece.cornerCount = 1;
  } else if (same(corners[0], corners[1]) || same(corners[1], corners[2]) ||
             same(corners[0], corners[2])) {
    piece.cornerCount = 2;
    if (same(corners[0], corners[1])) corners[1] = corners[2];
    corners[2] = corners[1];
  }
  for (int k = 0; k < 3; ++k) {
    piece.corners[k] = from.points[corners[k]];
    piece.cornerUpper[k] = pointUpper[corners[k]];
  }
  return piece;
}

/// The refinement of one direction: rounds of bounding and splitting (see certifiedHausdorff()).
class DirectedRefinement {
 public:
  DirectedRefinement(const HausdorffShape& from, const HausdorffShape& to, double tolerance,
                     const CertifiedHausdorffOptions& options, std::string stage)
      : from_(from),
        target_(to),
        tolerance_(tolerance),
        options_(options),
        stage_(std::move(stage)) {}

  DirectedHausdorffBracket run() {
    boundPoints();
    std::vector<Piece> pieces;
    pieces.reserve(from_.triangles.size());
    for (const TriangleIndices& triangle : from_.triangles) {
      pieces.push_back(initialPiece(from_, triangle, result_.pointDistances));
    }
    initialCount_ = static_cast<double>(pieces.size());
    while (!pieces.empty()) pieces = refineRound(pieces);
    finish();
    return std::move(result_);
  }

 private:
  // Certified distances of every point of `from`; the first lower bound.
  void boundPoints() {
    const std::vector<Eigen::Vector3d>& points = from_.points;
    std::vector<PointBound> bounds(points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          bounds[i] = target_.point(points[i]);
                        }
                      });
    result_.pointDistances.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      result_.pointDistances[i] = bounds[i].upper;
      // Only points that are corners of a primitive are points of the shape; all of them are
      // for the shapes this module makes, but a mesh may carry unused vertices.
      if (used(i)) witness_.offer(bounds[i].lower, points[i], bounds[i].closest);
    }
  }

  bool used(std::size_t point) {
    if (usedPoints_.empty()) {
      usedPoints_.assign(from_.points.size(), false);
      for (const TriangleIndices& triangle : from_.triangles) {
        for (const std::uint32_t corner : triangle) usedPoints_[corner] = true;
      }
    }
    return usedPoints_[point];
  }

  // One round: bound every piece, settle those within the tolerance (or not refinable), split
  // the others. Returns the children.
  std::vector<Piece> refineRound(const std::vector<Piece>& pieces) {
    const double threshold = witness_.lower + tolerance_;
    std::vector<double> uppers(pieces.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pieces.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          double upper = lipschitzUpper(pieces[i]);
                          if (upper > threshold) {
                            upper = target_.hullUpper(pieces[i].corners, threshold, upper);
                          }
                          uppers[i] = upper;
                        }
                      });
    std::vector<std::size_t> splitting;
    std::size_t childCount = 0;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      if (uppers[i] <= threshold || !refinable(pieces[i], childCount)) {
        settled_ = std::max(settled_, uppers[i]);
        if (uppers[i] > threshold) markUnconverged(pieces[i]);
        continue;
      }
      splitting.push_back(i);
      childCount += pieces[i].cornerCount == 3 ? 4 : 2;
    }
    std::vector<Piece> children = split(pieces, splitting);
    result_.primitivesRefined += splitting.size();
    reportProgress(children);
    return children;
  }

  bool refinable(const Piece& piece, std::size_t childrenSoFar) {
    if (piece.cornerCount == 1) return false;
    if (piece.depth >= options_.maxDepth) return false;
    return childrenSoFar + 4 <= options_.maxPieces;
  }

  void markUnconverged(const Piece& piece) {
    if (!result_.converged) return;
    result_.converged = false;
    if (piece.cornerCount == 1) {
      result_.warning = "the tolerance is below the rounding of the distances at a point";
    } else if (piece.depth >= options_.maxDepth) {
      result_.warning = "a primitive reached the subdivision limit (" +
                        std::to_string(options_.maxDepth) + " halvings) before the tolerance";
    } else {
      result_.warning = "the refinement reached its limit of " +
                        std::to_string(options_.maxPieces) + " pieces before the tolerance";
    }
  }

  // The children of the split pieces, in piece order, with their new corners bounded; the
  // lower bound and witness are updated in the same order.
  std::vector<Piece> split(const std::vector<Piece>& pieces,
                           const std::vector<std::size_t>& splitting) {
    std::vector<std::size_t> firstChild(splitting.size() + 1, 0);
    for (std::size_t s = 0; s < splitting.size(); ++s) {
      firstChild[s + 1] = firstChild[s] + (pieces[splitting[s]].cornerCount == 3 ? 4 : 2);
    }
    std::vector<Piece> children(firstChild.back());
    std::vector<Witness> found(splitting.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, splitting.size(), 8),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t s = range.begin(); s != range.end(); ++s) {
                          splitPiece(pieces[splitting[s]], &children[firstChild[s]], found[s]);
                        }
                      });
    for (const Witness& candidate : found) {
      witness_.offer(candidate.lower, candidate.point, candidate.closest);
    }
    return children;
  }

  // Splits at the midpoints of the edges: four triangles, or two segments.
  void splitPiece(const Piece& parent, Piece* children, Witness& found) const {
    const auto bounded = [&](const Eigen::Vector3d& point) {
      const PointBound bound = target_.point(point);
      found.offer(bound.lower, point, bound.closest);
      return bound.upper;
    };
    const std::array<Eigen::Vector3d, 3>& c = parent.corners;
    const auto make = [&](int index, const std::array<Eigen::Vector3d, 3>& corners,
                          const std::array<double, 3>& uppers) {
      Piece& child = children[index];
      child.corners = corners;
      child.cornerUpper = uppers;
      child.cornerCount = parent.cornerCount;
      child.depth = static_cast<std::uint8_t>(parent.depth + 1);
    };
    const std::array<double, 3>& d = parent.cornerUpper;
    if (parent.cornerCount == 2) {
      const Eigen::Vector3d middle = 0.5 * (c[0] + c[1]);
      const double m = bounded(middle);
      make(0, {c[0], middle, middle}, {d[0], m, m});
      make(1, {middle, c[1], c[1]}, {m, d[1], d[1]});
      return;
    }
    const Eigen::Vector3d ab = 0.5 * (c[0] + c[1]);
    const Eigen::Vector3d bc = 0.5 * (c[1] + c[2]);
    const Eigen::Vector3d ca = 0.5 * (c[2] + c[0]);
    const double mab = bounded(ab), mbc = bounded(bc), mca = bounded(ca);
    make(0, {c[0], ab, ca}, {d[0], mab, mca});
    make(1, {ab, c[1], bc}, {mab, d[1], mbc});
    make(2, {ca, bc, c[2]}, {mca, mbc, d[2]});
    make(3, {ab, bc, ca}, {mab, mbc, mca});
  }

  // The share of `from` (by primitive, a child counting a quarter or half of its parent) that is
  // settled.
  void reportProgress(const std::vector<Piece>& children) {
    if (children.empty()) return;
    result_.deepestLevel = std::max(result_.deepestLevel, int(children.front().depth));
    if (!options_.progress) return;
    double open = 0.0;
    for (const Piece& child : children) {
      open += std::ldexp(1.0, -(child.cornerCount == 3 ? 2 : 1) * child.depth);
    }
    options_.progress(stage_, std::clamp(1.0 - open / initialCount_, 0.0, 1.0));
  }

  // The corners of refined pieces are off the exact midpoints by at most u |midpoint| per
  // coordinate and level, on top of their parents' error: sqrt(3) (depth + 1) u s as a vector.
  void finish() {
    double scale = 0.0;
    for (const Eigen::Vector3d& point : from_.points) {
      scale = std::max(scale, detail::largestMagnitude(point));
    }
    const double corners = 2.0 * (result_.deepestLevel + 1) * kUnitRoundoff * scale;
    result_.lower = std::max(0.0, witness_.lower - corners);
    result_.upper = std::max(settled_, witness_.lower) + corners;
    result_.witness = witness_.point;
    result_.witnessClosest = witness_.closest;
    if (options_.progress) options_.progress(stage_, 1.0);
  }

  const HausdorffShape& from_;
  TargetDistance target_;
  double tolerance_;
  const CertifiedHausdorffOptions& options_;
  std::string stage_;
  DirectedHausdorffBracket result_;
  Witness witness_;
  double settled_ = 0.0;
  double initialCount_ = 1.0;
  std::vector<bool> usedPoints_;
};

void requireShape(const HausdorffShape& shape, const char* name) {
  if (shape.triangles.empty()) {
    throw InputError(std::string("shape ") + name + " has no primitives");
  }
  for (const Eigen::Vector3d& point : shape.points) {
    if (!point.allFinite()) {
      throw InputError(std::string("shape ") + name + " has a non-finite coordinate");
    }
  }
  for (const TriangleIndices& triangle : shape.triangles) {
    for (const std::uint32_t corner : triangle) {
      if (corner >= shape.points.size()) {
        throw InputError(std::string("a primitive of shape ") + name + " names point " +
                         std::to_string(corner) + " of " + std::to_string(shape.points.size()));
      }
    }
  }
  if (!(shape.approximationError >= 0.0) || !std::isfinite(shape.approximationError)) {
    throw InputError(std::string("shape ") + name + " has an invalid approximation error");
  }
}

void requireOptions(const CertifiedHausdorffOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance)) {
    throw InputError("the Hausdorff tolerance must be a positive finite number, not " +
                     formatNumber(options.tolerance));
  }
  if (options.maxDepth < 1 || options.maxDepth > 40) {
    throw InputError("the Hausdorff subdivision depth must be 1..40, not " +
                     std::to_string(options.maxDepth));
  }
  if (options.maxPieces < 4) throw InputError("the Hausdorff piece limit must be at least 4");
}

// Widens a bracket of the triangles' distance into one of the shapes' distance.
void widen(DirectedHausdorffBracket& bracket, double error) {
  bracket.lower = std::max(0.0, bracket.lower - error);
  bracket.upper += error;
}

// The tolerance the refinement of the triangles works to: the requested one less what the
// shapes' tessellation errors and the rounding of refined corners add to the bracket's width.
double refinementTolerance(const HausdorffShape& from, const HausdorffShape& to, double tolerance,
                           int maxDepth) {
  const double shapes = 2.0 * (from.approximationError + to.approximationError);
  if (!(tolerance > shapes)) {
    throw InputError("the tolerance " + formatNumber(tolerance) +
                     " is not larger than twice the shapes' tessellation errors (" +
                     formatNumber(shapes) + "): tessellate more finely");
  }
  double scale = 0.0;
  for (const HausdorffShape* shape : {&from, &to}) {
    for (const Eigen::Vector3d& point : shape->points) {
      scale = std::max(scale, detail::largestMagnitude(point));
    }
  }
  const double rounding = 4.0 * (maxDepth + 1) * kUnitRoundoff * scale;
  if (!(tolerance - shapes > 2.0 * rounding)) {
    throw InputError("the tolerance " + formatNumber(tolerance) +
                     " is below what double precision resolves at coordinates of magnitude " +
                     formatNumber(scale) + " (about " + formatNumber(2.0 * rounding) + ")");
  }
  return tolerance - shapes - rounding;
}

}  // namespace

DirectedHausdorffBracket directedHausdorff(const HausdorffShape& from, const HausdorffShape& to,
                                           double tolerance,
                                           const CertifiedHausdorffOptions& options) {
  requireShape(from, "A");
  requireShape(to, "B");
  CertifiedHausdorffOptions absolute = options;
  absolute.tolerance = tolerance;
  absolute.relative = false;
  requireOptions(absolute);
  DirectedRefinement refinement(
      from, to, refinementTolerance(from, to, tolerance, absolute.maxDepth), absolute, "h(A -> B)");
  DirectedHausdorffBracket bracket = refinement.run();
  widen(bracket, from.approximationError + to.approximationError);
  return bracket;
}

CertifiedHausdorff certifiedHausdorff(const HausdorffShape& a, const HausdorffShape& b,
                                      const CertifiedHausdorffOptions& options) {
  requireShape(a, "A");
  requireShape(b, "B");
  requireOptions(options);
  CertifiedHausdorff result;
  result.tolerance = options.tolerance;
  if (options.relative) {
    const double diagonal = combinedDiagonal(a, b);
    result.tolerance = diagonal > 0.0 ? options.tolerance * diagonal : options.tolerance;
  }
  const double refinement = refinementTolerance(a, b, result.tolerance, options.maxDepth);
  const double shapes = a.approximationError + b.approximationError;
  result.aToB = DirectedRefinement(a, b, refinement, options, "h(A -> B)").run();
  result.bToA = DirectedRefinement(b, a, refinement, options, "h(B -> A)").run();
  widen(result.aToB, shapes);
  widen(result.bToA, shapes);
  result.aToBIsLarger = result.aToB.lower >= result.bToA.lower;
  result.lower = std::max(result.aToB.lower, result.bToA.lower);
  result.upper = std::max(result.aToB.upper, result.bToA.upper);
  return result;
}

}  // namespace d2vdb
