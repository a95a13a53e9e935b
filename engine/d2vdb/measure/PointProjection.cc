// Point-curve projection by Bernstein root isolation of (C(t) - p) . C'(t) over each span, and
// the batch projection.
#include "d2vdb/measure/PointProjection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/measure/detail/BernsteinRoots.h"

namespace d2vdb {

using detail::findBernsteinRoots;
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

void requireFinitePoint(const Eigen::Vector3d& point) {
  if (!point.allFinite()) {
    throw InputError("point projection: the point (" + std::to_string(point.x()) + ", " +
                     std::to_string(point.y()) + ", " + std::to_string(point.z()) +
                     ") is not finite");
  }
}

double largestNorm(const BezierCurve& curve) {
  return curve.controlPoints().colwise().norm().maxCoeff();
}

// Noise levels of the first and second derivatives of |B(s) - p|^2 / 2 on one segment: values
// below them are indistinguishable from zero in floating point.
struct DerivativeNoise {
  double slope;
  double curvature;
};

DerivativeNoise derivativeNoise(const CurveProjector::Segment& segment,
                                const BezierCurve& shifted) {
  const BezierCurve velocity = segment.hodograph();
  const double offset = largestNorm(shifted);
  const double speed = largestNorm(velocity);
  const double acceleration = largestNorm(velocity.derivative());
  const double factor = 256.0 * (2 * segment.curve.degree() + 1) * kEpsilon;
  return {factor * offset * speed, factor * (speed * speed + offset * acceleration)};
}

// +1 when the distance grows when moving away from s along the segment in `direction` (+1
// forward, -1 backward), -1 when it shrinks, 0 when it is stationary to second order.
int trend(const CurveProjector::Segment& segment, const Eigen::Vector3d& point, double s,
          int direction, const DerivativeNoise& noise) {
  const BezierCurve hodograph = segment.hodograph();
  const Eigen::Vector3d offset = segment.curve.evaluate(s) - point;
  const Eigen::Vector3d velocity = hodograph.evaluate(s);
  const double slope = offset.dot(velocity);
  if (std::abs(slope) > noise.slope) return slope * direction > 0.0 ? 1 : -1;
  const double curvature = velocity.squaredNorm() + offset.dot(hodograph.derivative().evaluate(s));
  if (std::abs(curvature) > noise.curvature) return curvature > 0.0 ? 1 : -1;
  return 0;
}

// The extremum kind from the trends on both sides of a knot (an end of an open curve has one
// side only); nullopt when the distance rises on one side and falls on the other.
std::optional<ExtremumKind> kindFromTrends(std::optional<int> before, std::optional<int> after) {
  const int a = before ? *before : *after;
  const int b = after ? *after : *before;
  if (a >= 0 && b >= 0 && (a > 0 || b > 0)) return ExtremumKind::Minimum;
  if (a <= 0 && b <= 0 && (a < 0 || b < 0)) return ExtremumKind::Maximum;
  if (a == 0 && b == 0) return ExtremumKind::Degenerate;
  return std::nullopt;
}

}  // namespace

CurveProjector::CurveProjector(const BSplineCurve& curve)
    : closed_(curve.isClosed()), domain_(curve.domain()) {
  const std::vector<BezierSegment> pieces = curve.toBezierSegments();
  segments_.reserve(pieces.size());
  while (leafCount_ < static_cast<int>(pieces.size())) leafCount_ *= 2;
  boxTree_.resize(2 * static_cast<std::size_t>(leafCount_));
  for (const BezierSegment& piece : pieces) {
    boxTree_[static_cast<std::size_t>(leafCount_) + segments_.size()] =
        piece.curve.controlPointBounds();
    segments_.push_back(Segment{piece.curve, piece.interval});
  }
  for (int node = leafCount_ - 1; node >= 1; --node) {
    boxTree_[static_cast<std::size_t>(node)] = boxTree_[2 * static_cast<std::size_t>(node)].merged(
        boxTree_[2 * static_cast<std::size_t>(node) + 1]);
  }
  bounds_ = boxTree_[1];
}

NearestPoint CurveProjector::pointAt(const SegmentPoint& location,
                                     const Eigen::Vector3d& from) const {
  const Segment& segment = segments_[static_cast<std::size_t>(location.segment)];
  NearestPoint result;
  result.location = location;
  result.parameter = segment.interval.at(location.segmentParameter);
  result.point = segment.curve.evaluate(location.segmentParameter);
  result.squaredDistance = (result.point - from).squaredNorm();
  return result;
}

void CurveProjector::visitSegment(const Eigen::Vector3d& point, int index, bool pruneByCoefficients,
                                  NearestPoint& best) const {
  if (segmentBounds(index).squaredExteriorDistance(point) > best.squaredDistance) return;
  const Segment& segment = segments_[static_cast<std::size_t>(index)];
  const BezierCurve shifted = segment.curve.translated(-point);
  if (pruneByCoefficients) {
    const BernsteinPolynomial squared = dot(shifted, shifted);
    const double rounding = 64.0 * (squared.degree() + 1) * kEpsilon * squared.maxCoefficient();
    if (squared.minCoefficient() - rounding > best.squaredDistance) return;
  }
  const auto consider = [&](double s) {
    const double distance = (segment.curve.evaluate(s) - point).squaredNorm();
    if (distance < best.squaredDistance) best = pointAt({index, s}, point);
  };
  consider(0.0);
  consider(1.0);
  for (const double root : findBernsteinRoots(dot(shifted, segment.hodograph())).roots) {
    consider(root);
  }
}

NearestPoint CurveProjector::nearest(const Eigen::Vector3d& point,
                                     const std::optional<SegmentPoint>& hint) const {
  requireFinitePoint(point);
  NearestPoint best;
  best.squaredDistance = std::numeric_limits<double>::infinity();
  if (hint) {
    best = pointAt(*hint, point);
    visitSegment(point, hint->segment, false, best);  // it attains the bound: no pruning
  }
  // Depth-first through the box tree, the nearer child first.
  std::array<int, 2 * 64> stack{};
  std::size_t size = 0;
  stack[size++] = 1;
  while (size > 0) {
    const int node = stack[--size];
    const Eigen::AlignedBox3d& box = boxTree_[static_cast<std::size_t>(node)];
    if (box.isEmpty() || box.squaredExteriorDistance(point) > best.squaredDistance) continue;
    if (node >= leafCount_) {
      const int index = node - leafCount_;
      if (!hint || index != hint->segment) visitSegment(point, index, true, best);
      continue;
    }
    const int left = 2 * node;
    const int right = left + 1;
    const bool leftNearer =
        boxTree_[static_cast<std::size_t>(left)].squaredExteriorDistance(point) <=
        boxTree_[static_cast<std::size_t>(right)].squaredExteriorDistance(point);
    stack[size++] = leftNearer ? right : left;
    stack[size++] = leftNearer ? left : right;
  }
  return best;
}

bool CurveProjector::segmentsNear(const Eigen::AlignedBox3d& box, double squaredRadius,
                                  std::size_t limit, std::vector<int>& out) const {
  // Depth-first, left child first: leaves come out in segment order.
  std::array<int, 2 * 64> stack{};
  std::size_t size = 0;
  std::size_t found = 0;
  stack[size++] = 1;
  while (size > 0) {
    const int node = stack[--size];
    const Eigen::AlignedBox3d& nodeBox = boxTree_[static_cast<std::size_t>(node)];
    if (nodeBox.isEmpty() || nodeBox.squaredExteriorDistance(box) > squaredRadius) continue;
    if (node >= leafCount_) {
      if (++found > limit) return false;
      out.push_back(node - leafCount_);
      continue;
    }
    stack[size++] = 2 * node + 1;
    stack[size++] = 2 * node;
  }
  return true;
}

NearestPoint CurveProjector::nearest(const Eigen::Vector3d& point,
                                     const std::vector<int>& candidateSegments,
                                     const std::optional<SegmentPoint>& hint) const {
  requireFinitePoint(point);
  if (candidateSegments.empty() && !hint) {
    throw InputError("point projection: no segment to project onto");
  }
  NearestPoint best;
  best.squaredDistance = std::numeric_limits<double>::infinity();
  if (hint) best = pointAt(*hint, point);

  // The hint's segment, or else the candidate whose box is nearest, goes first, then the others
  // in list order: deterministic, and the early bound prunes most of them.
  std::optional<std::size_t> first;
  if (hint) {
    const auto found = std::find(candidateSegments.begin(), candidateSegments.end(), hint->segment);
    if (found != candidateSegments.end()) {
      first = static_cast<std::size_t>(found - candidateSegments.begin());
    }
  } else {
    double nearestBox = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < candidateSegments.size(); ++k) {
      const double distance = segmentBounds(candidateSegments[k]).squaredExteriorDistance(point);
      if (distance < nearestBox) {
        nearestBox = distance;
        first = k;
      }
    }
  }
  if (first) visitSegment(point, candidateSegments[*first], !hint, best);
  for (std::size_t k = 0; k < candidateSegments.size(); ++k) {
    if (!first || k != *first) visitSegment(point, candidateSegments[k], true, best);
  }
  return best;
}

PointProjection CurveProjector::project(const Eigen::Vector3d& point) const {
  return project(point, std::numeric_limits<double>::infinity());
}

PointProjection CurveProjector::project(const Eigen::Vector3d& point, double searchRadius) const {
  requireFinitePoint(point);
  if (!(searchRadius >= 0.0)) {
    throw InputError("point projection: the search radius must be >= 0");
  }
  PointProjection result;
  result.distance = std::numeric_limits<double>::infinity();
  const auto considerNearest = [&](double parameter, const Eigen::Vector3d& curvePoint) {
    const double distance = (curvePoint - point).norm();
    if (distance < result.distance) {
      result.distance = distance;
      result.parameter = parameter;
      result.point = curvePoint;
    }
  };
  const auto addExtremum = [&](double parameter, const Eigen::Vector3d& curvePoint,
                               ExtremumKind kind, bool atEndPoint) {
    result.extrema.push_back(
        {parameter, curvePoint, (curvePoint - point).norm(), kind, atEndPoint});
  };

  std::vector<DerivativeNoise> noise;
  noise.reserve(segments_.size());
  for (const Segment& segment : segments_) {
    noise.push_back(derivativeNoise(segment, segment.curve.translated(-point)));
  }

  const std::size_t count = segments_.size();
  for (std::size_t i = 0; i < count; ++i) {
    const Segment& segment = segments_[i];
    // The knot at the start of this segment: one-sided trends from both neighbours.
    const bool hasBefore = i > 0 || closed_;
    const std::size_t previous = i > 0 ? i - 1 : count - 1;
    const std::optional<int> before =
        hasBefore ? std::optional<int>(trend(segments_[previous], point, 1.0, -1, noise[previous]))
                  : std::nullopt;
    const std::optional<int> after = trend(segment, point, 0.0, 1, noise[i]);
    const Eigen::Vector3d knotPoint = segment.curve.evaluate(0.0);
    considerNearest(segment.interval.start, knotPoint);
    if (const auto kind = kindFromTrends(before, after)) {
      addExtremum(segment.interval.start, knotPoint, *kind, !closed_ && i == 0);
    }

    // Interior solutions of (B(s) - p) . B'(s) = 0, classified by the second derivative.
    if (segmentBounds(static_cast<int>(i)).exteriorDistance(point) > searchRadius) continue;
    const BezierCurve shifted = segment.curve.translated(-point);
    const BezierCurve hodograph = segment.hodograph();
    const BezierCurve secondHodograph = hodograph.derivative();
    for (const double root : findBernsteinRoots(dot(shifted, hodograph)).roots) {
      if (root <= 0.0 || root >= 1.0) continue;  // knots are handled above
      const Eigen::Vector3d curvePoint = segment.curve.evaluate(root);
      const Eigen::Vector3d velocity = hodograph.evaluate(root);
      const double curvature =
          velocity.squaredNorm() + (curvePoint - point).dot(secondHodograph.evaluate(root));
      const ExtremumKind kind = curvature > noise[i].curvature    ? ExtremumKind::Minimum
                                : curvature < -noise[i].curvature ? ExtremumKind::Maximum
                                                                  : ExtremumKind::Degenerate;
      const double parameter = segment.interval.at(root);
      considerNearest(parameter, curvePoint);
      addExtremum(parameter, curvePoint, kind, false);
    }
  }
  if (!closed_) {  // the end of an open curve
    const Segment& last = segments_.back();
    const Eigen::Vector3d endPoint = last.curve.evaluate(1.0);
    considerNearest(last.interval.end, endPoint);
    if (const auto kind = kindFromTrends(trend(last, point, 1.0, -1, noise.back()), std::nullopt)) {
      addExtremum(last.interval.end, endPoint, *kind, true);
    }
  }

  // A stationary point at (or within rounding of) a knot can be reported twice: once as an
  // interior root, once as the knot. Keep one per kind within a parameter tolerance.
  const double mergeDistance = 1e-9 * domain_.length();
  std::vector<CurveExtremum> merged;
  for (const CurveExtremum& extremum : result.extrema) {
    if (!merged.empty() && merged.back().kind == extremum.kind &&
        extremum.parameter - merged.back().parameter <= mergeDistance) {
      CurveExtremum& kept = merged.back();
      const bool better = extremum.kind == ExtremumKind::Maximum
                              ? extremum.distance > kept.distance
                              : extremum.distance < kept.distance;
      if (better || extremum.atEndPoint) {
        const bool endPoint = kept.atEndPoint || extremum.atEndPoint;
        kept = extremum;
        kept.atEndPoint = endPoint;
      }
      continue;
    }
    merged.push_back(extremum);
  }
  result.extrema = std::move(merged);
  return result;
}

std::vector<PointProjection> CurveProjector::project(
    const std::vector<Eigen::Vector3d>& points) const {
  for (const Eigen::Vector3d& point : points) requireFinitePoint(point);
  std::vector<PointProjection> results(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        results[i] = project(points[i]);
                      }
                    });
  return results;
}

PointProjection projectPoint(const BSplineCurve& curve, const Eigen::Vector3d& point) {
  return CurveProjector(curve).project(point);
}

std::vector<PointProjection> projectPoints(const BSplineCurve& curve,
                                           const std::vector<Eigen::Vector3d>& points) {
  return CurveProjector(curve).project(points);
}

}  // namespace d2vdb
