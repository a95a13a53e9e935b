// Exact squared-distance approximants of curves, computed from the curve itself: B-spline curves
// (by exact projection) and polylines (with curvature estimated from the vertices). They serve
// directly as fitting targets and are what curve fields sample at their voxel centres.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

#include "d2vdb/field/SquaredDistanceTarget.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

class CurveProjector;

/// A polyline: vertices in order; a closed polyline joins the last vertex to the first (the first
/// vertex is not repeated). 2D polylines have z = 0.
struct Polyline {
  std::vector<Eigen::Vector3d> points;
  bool closed = false;
  int dimension = 3;  ///< 2 or 3
};

/// Exact approximants of a curve target (TargetKind::Curve), answered anywhere in its domain.
///
/// B-spline curves: the footpoint is the exact nearest point (CurveProjector::nearest, Bézier root
/// isolation), tangent, curvature and principal normal come from the curve's derivatives there.
/// Polylines: the footpoint is the exact nearest point of the polyline; the tangent is the
/// segment's direction (at a vertex footpoint, the mean of the adjacent directions made orthogonal
/// to the direction toward the query point); the curvature vector kappa N is the one of the
/// circle through each vertex and its two neighbours (an open polyline's ends take their
/// neighbour's),
/// interpolated linearly along each segment and made orthogonal to the tangent. So a polyline
/// sampled from a smooth curve answers like that curve, up to the sampling's chord error.
/// End points of open curves give kFlagEndPoint approximants (PDM form).
///
/// The domain is the curve's bounding box padded by `domainPadding` times its largest side on
/// every side (a degenerate box gets at least 1 unit). Immutable; thread-safe.
class CurveTarget final : public SquaredDistanceTarget {
 public:
  /// Target from a B-spline curve (its own copy). Throws InputError for a curve whose control
  /// points all coincide (no tangent anywhere) or a negative/NaN padding.
  explicit CurveTarget(const BSplineCurve& curve, double domainPadding = 0.5);

  /// Target from a polyline. Throws InputError for fewer than 2 distinct points, non-finite
  /// coordinates, a closed polyline of fewer than 3 points, a 2D polyline with z != 0, or a
  /// negative/NaN padding. Consecutive duplicate points are dropped.
  explicit CurveTarget(Polyline polyline, double domainPadding = 0.5);

  ~CurveTarget() override;
  CurveTarget(CurveTarget&&) noexcept;
  CurveTarget& operator=(CurveTarget&&) noexcept;

  TargetKind kind() const override { return TargetKind::Curve; }
  Eigen::AlignedBox3d domain() const override { return domain_; }
  Approximant approximantAt(const Eigen::Vector3d& point) const override;
  std::string describe() const override;
  /// A polyline's mean segment length (its approximants interpolate the curvature between
  /// vertices, so they resolve nothing finer than the vertex spacing); 0 for a spline.
  double resolvedLength() const override;

  /// The approximant at `point` without the domain check (for field construction, which samples
  /// a padded box). Throws InputError when `point` is not finite.
  Approximant approximantAtAnyPoint(const Eigen::Vector3d& point) const;

  /// Bounding box of the curve itself (control points for splines: a superset).
  const Eigen::AlignedBox3d& curveBounds() const { return curveBounds_; }
  /// 2 for planar curves in z = 0 (2D input), else 3.
  int dimension() const { return dimension_; }
  /// Approximate length (polyline length, or the length of a fine sampling of the spline).
  double length() const { return length_; }
  /// Points along the curve at spacing at most `spacing` (world), both ends (or the whole loop)
  /// included; used for bounds and seeding. InputError for a non-positive spacing.
  std::vector<Eigen::Vector3d> samplePoints(double spacing) const;
  /// Optional label for describe() (e.g. the file name).
  void setLabel(std::string label) { label_ = std::move(label); }

 private:
  Approximant splineApproximant(const Eigen::Vector3d& point) const;
  Approximant polylineApproximant(const Eigen::Vector3d& point) const;

  std::unique_ptr<BSplineCurve> spline_;
  std::unique_ptr<CurveProjector> projector_;
  Polyline polyline_;
  std::vector<Eigen::Vector3d> vertexCurvature_;     // kappa N at each polyline vertex
  std::vector<Eigen::AlignedBox3d> segmentBoxTree_;  // implicit binary tree over segments
  int segmentLeafCount_ = 1;
  Eigen::AlignedBox3d curveBounds_;
  Eigen::AlignedBox3d domain_;
  int dimension_ = 3;
  double length_ = 0.0;
  std::string label_;
};

}  // namespace d2vdb
