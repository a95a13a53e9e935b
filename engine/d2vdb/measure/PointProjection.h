// Point–curve projection: every local extremum of the distance from a point to a B-spline curve,
// and the nearest point, by Bézier root isolation (Chen, Ma, Xu and Paul, "Computing the Hausdorff
// distance between two B-spline curves", 2010; engine/README.md).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>
#include <vector>

#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// Kind of a local extremum of the distance t -> |C(t) - p|.
enum class ExtremumKind {
  Minimum,    ///< locally closest
  Maximum,    ///< locally farthest
  Degenerate  ///< stationary to second order (e.g. p at a centre of curvature, a constant piece)
};

/// One local extremum of the distance along the curve.
struct CurveExtremum {
  double parameter = 0.0;                           ///< t in the curve's domain
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< C(t)
  double distance = 0.0;                            ///< |C(t) - p|, world units
  ExtremumKind kind = ExtremumKind::Minimum;
  bool atEndPoint = false;  ///< t is an end of an open curve's domain
};

/// Result of projecting one point p onto a curve.
struct PointProjection {
  double parameter = 0.0;                           ///< t of the nearest point (global minimum)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< C(t), the nearest point
  double distance = 0.0;                            ///< min_t |C(t) - p|
  /// Every local extremum of |C(t) - p| (interior solutions of (C(t) - p) . C'(t) = 0, knots
  /// where the distance has a corner extremum, and the ends of open curves), ascending in t.
  std::vector<CurveExtremum> extrema;
};

/// A point on one Bézier segment of the curve a CurveProjector holds.
struct SegmentPoint {
  int segment = -1;               ///< index into CurveProjector::segments()
  double segmentParameter = 0.0;  ///< s in [0, 1] on that segment
};

/// The nearest point as CurveProjector::nearest() reports it.
struct NearestPoint {
  SegmentPoint location;                            ///< where it lies
  double parameter = 0.0;                           ///< t in the curve's domain
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< C(t)
  double squaredDistance = 0.0;                     ///< |C(t) - p|^2, world units squared
};

/// A B-spline curve prepared for repeated projections: its Bézier segments (one per non-empty
/// knot span), their first and second hodographs and control-point bounding boxes.
///
/// Method (Chen et al. 2010): on every segment the projection condition f(s) = (B(s) - p) . B'(s)
/// is written in Bernstein form (degree 2n - 1) and its roots are isolated by findBernsteinRoots()
/// (convex-hull pruning, subdivision, Newton polish). Knots and the ends of open curves are
/// examined as well, so corner extrema are found. Immutable after construction; all members are
/// thread-safe.
class CurveProjector {
 public:
  /// One polynomial piece: B(s) = C(interval.at(s)), s in [0, 1]; derivatives are in s. Only
  /// the curve is stored (a Bézier curve has fixed, degree-independent storage), so that many
  /// segments stay compact; hodographs are formed on demand.
  struct Segment {
    BezierCurve curve;
    ParameterInterval interval;  ///< the knot span in the curve's parameter

    /// B'(s), O(degree).
    BezierCurve hodograph() const { return curve.derivative(); }
  };

  /// Extracts the segments of `curve` (its own copy; the curve may be discarded afterwards).
  explicit CurveProjector(const BSplineCurve& curve);

  /// The Bézier segments in parameter order.
  const std::vector<Segment>& segments() const { return segments_; }
  /// Bounding box of the control points of segment `index` (contains that piece); no bounds
  /// check.
  const Eigen::AlignedBox3d& segmentBounds(int index) const {
    return boxTree_[static_cast<std::size_t>(leafCount_ + index)];
  }
  /// True when the curve is closed (periodic): no end points.
  bool isClosed() const { return closed_; }
  /// The curve's parameter domain.
  ParameterInterval domain() const { return domain_; }
  /// Bounding box of all control points (contains the curve).
  const Eigen::AlignedBox3d& bounds() const { return bounds_; }

  /// The nearest point of the curve and every local extremum of the distance to `point`.
  /// Throws InputError when `point` is not finite.
  PointProjection project(const Eigen::Vector3d& point) const;

  /// project() restricted to the curve within `searchRadius` of `point`: interior extrema are
  /// sought only on segments whose bounding box is that near (knots and ends are always
  /// examined), so the nearest point is still exact when it lies within the radius. Throws
  /// InputError when `point` is not finite or the radius is negative or NaN.
  PointProjection project(const Eigen::Vector3d& point, double searchRadius) const;

  /// project() for every point, in parallel (TBB); result i belongs to points[i], identical for
  /// any thread count. Throws InputError when a point is not finite.
  std::vector<PointProjection> project(const std::vector<Eigen::Vector3d>& points) const;

  /// Only the nearest point (no extrema list), optionally starting from `hint`, a known point of
  /// the curve whose distance serves as the initial bound. Segments are visited through a binary
  /// tree of their bounding boxes, nearer boxes first; a subtree is skipped when its box, and a
  /// segment when the smallest Bernstein coefficient of |B(s) - p|^2, is farther than the best
  /// point so far, so a query costs about O(log n) segments. Ties go to the segment visited
  /// first (deterministic). Throws InputError when `point` is not finite.
  NearestPoint nearest(const Eigen::Vector3d& point,
                       const std::optional<SegmentPoint>& hint = std::nullopt) const;

  /// The nearest point among the segments listed in `candidateSegments` (indices into
  /// segments()), starting from `hint` (returned if nothing listed is closer). The list is
  /// scanned: the hint's segment (or else the one with the nearest box) first, then the others
  /// in list order. The Hausdorff computation uses it with candidate lists it has proved
  /// sufficient. Same pruning and failure behaviour as nearest(point); an empty list without a
  /// hint throws InputError.
  NearestPoint nearest(const Eigen::Vector3d& point, const std::vector<int>& candidateSegments,
                       const std::optional<SegmentPoint>& hint) const;

  /// Appends to `out`, in increasing order, the segments whose bounding box lies within
  /// sqrt(`squaredRadius`) of `box`, found through the box tree in O(log n + found) box tests.
  /// Stops and returns false as soon as more than `limit` are found (`out` is then incomplete);
  /// returns true otherwise.
  bool segmentsNear(const Eigen::AlignedBox3d& box, double squaredRadius, std::size_t limit,
                    std::vector<int>& out) const;
  /// The curve point at `location` (no bounds check on the segment index), with its parameter
  /// and its squared distance to `from`.
  NearestPoint pointAt(const SegmentPoint& location, const Eigen::Vector3d& from) const;

 private:
  // Updates `best` with the nearest point of segment `index` when it can beat it.
  void visitSegment(const Eigen::Vector3d& point, int index, bool pruneByCoefficients,
                    NearestPoint& best) const;

  std::vector<Segment> segments_;
  bool closed_;
  ParameterInterval domain_;
  Eigen::AlignedBox3d bounds_;
  // Implicit complete binary tree of bounding boxes: node 1 is the root, node k has children 2k
  // and 2k + 1, leaves leafCount_ + i hold segment i (empty boxes pad to a power of two).
  int leafCount_ = 1;
  std::vector<Eigen::AlignedBox3d> boxTree_;
};

/// CurveProjector(curve).project(point): the nearest point and all local distance extrema.
PointProjection projectPoint(const BSplineCurve& curve, const Eigen::Vector3d& point);

/// CurveProjector(curve).project(points): the batch version, in parallel, deterministic.
std::vector<PointProjection> projectPoints(const BSplineCurve& curve,
                                           const std::vector<Eigen::Vector3d>& points);

}  // namespace d2vdb
