// Exact approximants of B-spline and polyline curve targets (CurveTarget.h).
#include "d2vdb/field/CurveTarget.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/detail/DomainError.h"
#include "d2vdb/measure/PointProjection.h"

namespace d2vdb {
namespace {

// Messages show points with 9 significant digits.
constexpr int kCurveDigits = 9;

/// Completes an approximant's direction fields: `normal` from footpoint toward the point (or any
/// unit vector orthogonal to the tangent when the point lies on the curve).
void setDirectionToward(Approximant& result, const Eigen::Vector3d& point) {
  const Eigen::Vector3d offset = point - result.footpoint;
  result.distance = offset.norm();
  const double scale = std::max(1.0, result.footpoint.cwiseAbs().maxCoeff());
  if (result.distance > 1e-12 * scale) {
    result.normal = offset / result.distance;
  } else {
    result.normal = result.tangent.unitOrthogonal();
  }
}

Eigen::AlignedBox3d paddedDomain(const Eigen::AlignedBox3d& bounds, double padding) {
  if (!(padding >= 0.0) || !std::isfinite(padding)) {
    throw InputError("the domain padding must be a finite number >= 0");
  }
  const double size = std::max(bounds.sizes().maxCoeff(), 1e-300);
  const double pad = std::max(padding * size, size > 0.0 ? 0.0 : 1.0);
  Eigen::AlignedBox3d domain = bounds;
  domain.min().array() -= pad;
  domain.max().array() += pad;
  return domain;
}

/// Squared distance from `p` to an axis-aligned box (0 inside).
double boxSquaredDistance(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& p) {
  if (box.isEmpty()) return std::numeric_limits<double>::infinity();
  return box.squaredExteriorDistance(p);
}

}  // namespace

CurveTarget::CurveTarget(const BSplineCurve& curve, double domainPadding)
    : spline_(std::make_unique<BSplineCurve>(curve)),
      projector_(std::make_unique<CurveProjector>(curve)),
      dimension_(curve.dimension()) {
  const auto& points = curve.controlPoints();
  bool allEqual = true;
  for (const auto& p : points) allEqual = allEqual && (p - points.front()).norm() == 0.0;
  if (allEqual) {
    throw InputError("curve target: all control points coincide at " +
                     formatPoint(points.front(), kCurveDigits) + "; the curve has no tangent");
  }
  curveBounds_ = projector_->bounds();
  domain_ = paddedDomain(curveBounds_, domainPadding);
  const auto samples = curve.sample(std::max(64, 16 * curve.controlPointCount()));
  for (std::size_t i = 1; i < samples.size(); ++i) length_ += (samples[i] - samples[i - 1]).norm();
}

CurveTarget::CurveTarget(Polyline polyline, double domainPadding) : dimension_(polyline.dimension) {
  if (polyline.dimension != 2 && polyline.dimension != 3) {
    throw InputError("polyline target: the dimension must be 2 or 3, not " +
                     std::to_string(polyline.dimension));
  }
  std::vector<Eigen::Vector3d> points;
  points.reserve(polyline.points.size());
  for (std::size_t i = 0; i < polyline.points.size(); ++i) {
    const Eigen::Vector3d& p = polyline.points[i];
    if (!p.allFinite()) {
      throw InputError("polyline target: point " + std::to_string(i) + " is not finite");
    }
    if (polyline.dimension == 2 && p.z() != 0.0) {
      throw InputError("polyline target: point " + std::to_string(i) +
                       " of a 2D polyline has z = " + std::to_string(p.z()) + " (must be 0)");
    }
    if (points.empty() || (p - points.back()).norm() > 0.0) points.push_back(p);
  }
  if (polyline.closed && points.size() > 1 && (points.front() - points.back()).norm() == 0.0) {
    points.pop_back();
  }
  if (points.size() < 2) {
    throw InputError("polyline target: needs at least 2 distinct points, got " +
                     std::to_string(points.size()));
  }
  if (polyline.closed && points.size() < 3) {
    throw InputError("polyline target: a closed polyline needs at least 3 distinct points");
  }
  polyline_.points = std::move(points);
  polyline_.closed = polyline.closed;
  polyline_.dimension = polyline.dimension;

  const auto& v = polyline_.points;
  const std::size_t n = v.size();
  const std::size_t segmentCount = polyline_.closed ? n : n - 1;
  curveBounds_.setEmpty();
  for (const auto& p : v) curveBounds_.extend(p);
  domain_ = paddedDomain(curveBounds_, domainPadding);
  for (std::size_t i = 0; i < segmentCount; ++i) length_ += (v[(i + 1) % n] - v[i]).norm();

  // Curvature vector of the circle through each vertex and its neighbours.
  vertexCurvature_.assign(n, Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    if (!polyline_.closed && (i == 0 || i + 1 == n)) continue;
    const Eigen::Vector3d& prev = v[(i + n - 1) % n];
    const Eigen::Vector3d& next = v[(i + 1) % n];
    const Eigen::Vector3d a = prev - v[i], b = next - v[i];
    const Eigen::Vector3d axb = a.cross(b);
    const double denominator = 2.0 * axb.squaredNorm();
    if (!(denominator > 0.0)) continue;  // collinear: zero curvature
    // Circumcentre relative to v[i].
    const Eigen::Vector3d center =
        (a.squaredNorm() * b - b.squaredNorm() * a).cross(axb) / denominator;
    vertexCurvature_[i] = center / center.squaredNorm();  // kappa N = (c - v) / |c - v|^2
  }

  // Open ends: the curvature of the nearest interior vertex (a polyline sampled from a smooth
  // curve keeps bending up to its end; zero there would fade the curvature along the end segment).
  if (!polyline_.closed && n >= 3) {
    vertexCurvature_.front() = vertexCurvature_[1];
    vertexCurvature_.back() = vertexCurvature_[n - 2];
  }

  // Implicit binary tree of segment bounding boxes.
  segmentLeafCount_ = 1;
  while (segmentLeafCount_ < static_cast<int>(segmentCount)) segmentLeafCount_ *= 2;
  segmentBoxTree_.assign(2 * static_cast<std::size_t>(segmentLeafCount_), Eigen::AlignedBox3d());
  for (auto& box : segmentBoxTree_) box.setEmpty();
  for (std::size_t i = 0; i < segmentCount; ++i) {
    Eigen::AlignedBox3d box(v[i]);
    box.extend(v[(i + 1) % n]);
    segmentBoxTree_[segmentLeafCount_ + i] = box;
  }
  for (int node = segmentLeafCount_ - 1; node >= 1; --node) {
    segmentBoxTree_[node] = segmentBoxTree_[2 * node].merged(segmentBoxTree_[2 * node + 1]);
  }
}

CurveTarget::~CurveTarget() = default;
CurveTarget::CurveTarget(CurveTarget&&) noexcept = default;
CurveTarget& CurveTarget::operator=(CurveTarget&&) noexcept = default;

double CurveTarget::resolvedLength() const {
  if (spline_) return 0.0;
  const std::size_t n = polyline_.points.size();
  const std::size_t segments = polyline_.closed ? n : n - 1;
  return segments > 0 ? length_ / static_cast<double>(segments) : 0.0;
}

std::string CurveTarget::describe() const {
  std::string what = spline_
                         ? "B-spline curve (degree " + std::to_string(spline_->degree()) + ", " +
                               std::to_string(spline_->controlPointCount()) + " control points)"
                         : std::string(polyline_.closed ? "closed" : "open") + " polyline (" +
                               std::to_string(polyline_.points.size()) + " points)";
  if (!label_.empty()) what += " from " + label_;
  return what;
}

Approximant CurveTarget::approximantAt(const Eigen::Vector3d& point) const {
  if (!point.allFinite()) throw InputError("curve target: the query point is not finite");
  if (!domain_.contains(point)) {
    detail::throwOutsideDomain(point, domain_, describe(), kCurveDigits);
  }
  return approximantAtAnyPoint(point);
}

Approximant CurveTarget::approximantAtAnyPoint(const Eigen::Vector3d& point) const {
  if (!point.allFinite()) throw InputError("curve target: the query point is not finite");
  return spline_ ? splineApproximant(point) : polylineApproximant(point);
}

Approximant CurveTarget::splineApproximant(const Eigen::Vector3d& point) const {
  const NearestPoint nearest = projector_->nearest(point);
  const CurveDerivatives derivatives = spline_->derivatives(nearest.parameter);
  Approximant result;
  result.kind = TargetKind::Curve;
  result.origin = point;
  result.footpoint = nearest.point;
  const double speed = derivatives.first.norm();
  result.tangent = speed > 0.0 ? Eigen::Vector3d(derivatives.first / speed)
                               : Eigen::Vector3d::UnitY();  // a stationary point: any unit vector
  setDirectionToward(result, point);
  // An end point (or a corner) when the offset is not orthogonal to the tangent.
  if (result.distance > 0.0 && std::abs(result.normal.dot(result.tangent)) > 1e-6) {
    result.flags |= kFlagEndPoint;
    result.normal = (point - result.footpoint) / result.distance;
    // Keep the frame orthonormal: the tangent is made orthogonal to the normal.
    const Eigen::Vector3d t = result.tangent - result.tangent.dot(result.normal) * result.normal;
    result.tangent =
        t.norm() > 1e-12 ? Eigen::Vector3d(t.normalized()) : result.normal.unitOrthogonal();
  }
  if (speed > 0.0) {
    const Eigen::Vector3d curvatureVector =
        (derivatives.second - derivatives.second.dot(result.tangent) * result.tangent) /
        (speed * speed);
    result.k1 = curvatureVector.norm();
    if (result.k1 > 0.0) result.principalNormal = curvatureVector / result.k1;
  }
  return result;
}

Approximant CurveTarget::polylineApproximant(const Eigen::Vector3d& point) const {
  const auto& v = polyline_.points;
  const std::size_t n = v.size();
  // Nearest segment through the box tree, nearer children first; ties to the lower index.
  double best = std::numeric_limits<double>::infinity();
  std::size_t bestSegment = 0;
  double bestLambda = 0.0;
  // Depth-first: at most one pending sibling per level of the tree (depth < 64 for any size
  // that fits in memory), so a fixed array replaces a heap allocation per query.
  std::array<int, 128> stack;
  int pending = 0;
  stack[pending++] = 1;
  while (pending > 0) {
    const int node = stack[--pending];
    if (boxSquaredDistance(segmentBoxTree_[node], point) > best) continue;
    if (node >= segmentLeafCount_) {
      const std::size_t i = static_cast<std::size_t>(node - segmentLeafCount_);
      const Eigen::Vector3d& a = v[i];
      const Eigen::Vector3d& b = v[(i + 1) % n];
      const Eigen::Vector3d ab = b - a;
      const double lambda = std::clamp((point - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const double squared = (a + lambda * ab - point).squaredNorm();
      if (squared < best || (squared == best && i < bestSegment)) {
        best = squared;
        bestSegment = i;
        bestLambda = lambda;
      }
      continue;
    }
    const double left = boxSquaredDistance(segmentBoxTree_[2 * node], point);
    const double right = boxSquaredDistance(segmentBoxTree_[2 * node + 1], point);
    if (left <= right) {
      stack[pending++] = 2 * node + 1;
      stack[pending++] = 2 * node;
    } else {
      stack[pending++] = 2 * node;
      stack[pending++] = 2 * node + 1;
    }
  }

  const std::size_t i = bestSegment;
  const std::size_t j = (i + 1) % n;
  const Eigen::Vector3d direction = (v[j] - v[i]).normalized();
  Approximant result;
  result.kind = TargetKind::Curve;
  result.origin = point;
  result.footpoint = v[i] + bestLambda * (v[j] - v[i]);
  result.tangent = direction;
  setDirectionToward(result, point);

  const bool atStart = bestLambda <= 0.0, atEnd = bestLambda >= 1.0;
  if (atStart || atEnd) {
    // A vertex footpoint: the mean of the adjacent directions, made orthogonal to the normal.
    const std::size_t vertex = atStart ? i : j;
    const bool isEnd = !polyline_.closed && (vertex == 0 || vertex + 1 == n);
    Eigen::Vector3d tangent = direction;
    if (!isEnd) {
      const Eigen::Vector3d before = (v[vertex] - v[(vertex + n - 1) % n]).normalized();
      const Eigen::Vector3d after = (v[(vertex + 1) % n] - v[vertex]).normalized();
      tangent = (before + after).normalized();
    }
    if (result.distance > 0.0) {
      const Eigen::Vector3d t = tangent - tangent.dot(result.normal) * result.normal;
      tangent = t.norm() > 1e-9 ? Eigen::Vector3d(t.normalized()) : result.normal.unitOrthogonal();
      if (isEnd && std::abs(direction.dot(result.normal)) > 1e-6) result.flags |= kFlagEndPoint;
    }
    result.tangent = tangent;
  }
  // Curvature vector interpolated along the segment, orthogonal to the tangent.
  const double lambda = std::clamp(bestLambda, 0.0, 1.0);
  Eigen::Vector3d curvatureVector =
      (1.0 - lambda) * vertexCurvature_[i] + lambda * vertexCurvature_[j];
  curvatureVector -= curvatureVector.dot(result.tangent) * result.tangent;
  result.k1 = curvatureVector.norm();
  if (result.k1 > 0.0) result.principalNormal = curvatureVector / result.k1;
  return result;
}

std::vector<Eigen::Vector3d> CurveTarget::samplePoints(double spacing) const {
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InputError("curve sampling: the spacing must be a positive finite number");
  }
  std::vector<Eigen::Vector3d> samples;
  if (spline_) {
    const auto count = static_cast<long>(std::ceil(length_ / spacing * 1.5)) + 2;
    // Uniform in parameter with a safety factor for uneven speed, refined where gaps remain.
    const auto coarse = spline_->sample(static_cast<int>(std::min<long>(count, 50'000'000L)));
    samples.push_back(coarse.front());
    for (std::size_t k = 1; k < coarse.size(); ++k) {
      const double gap = (coarse[k] - coarse[k - 1]).norm();
      const int extra = static_cast<int>(std::floor(gap / spacing));
      for (int e = 1; e <= extra; ++e) {
        samples.push_back(coarse[k - 1] + (coarse[k] - coarse[k - 1]) * (e / (extra + 1.0)));
      }
      samples.push_back(coarse[k]);
    }
    return samples;
  }
  const auto& v = polyline_.points;
  const std::size_t n = v.size();
  const std::size_t segmentCount = polyline_.closed ? n : n - 1;
  for (std::size_t i = 0; i < segmentCount; ++i) {
    const Eigen::Vector3d& a = v[i];
    const Eigen::Vector3d& b = v[(i + 1) % n];
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
    for (int s = 0; s < steps; ++s) samples.push_back(a + (b - a) * (double(s) / steps));
  }
  if (!polyline_.closed) samples.push_back(v.back());
  return samples;
}

}  // namespace d2vdb
