// Initial surfaces for the surface fitters: planes, cylinders and tori placed from the principal
// axes of the target's points.
#include "d2vdb/fit/InitialSurface.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/spline/BSplineCurve.h"
#include "d2vdb/spline/KnotVector.h"

namespace d2vdb {
namespace {

constexpr double kTwoPi = 6.283185307179586476925;

void checkDirection(int degree, int count, bool closed, const char* name) {
  if (degree < 1 || degree > kMaxSplineDegree) {
    throw InputError(std::string("the degree in ") + name + " must be 1.." +
                     std::to_string(kMaxSplineDegree) + ", got " + std::to_string(degree));
  }
  if (count < degree + 1) {
    throw InputError(std::string("a ") + (closed ? "closed" : "open") + " direction of degree " +
                     std::to_string(degree) + " needs at least " + std::to_string(degree + 1) +
                     " control points, but " + name + " has " + std::to_string(count) +
                     (closed ? "" : " (the degree must be below the control-point count)"));
  }
}

/// Greville abscissae of the clamped uniform knot vector on [0, 1] (exact linear reproduction).
std::vector<double> greville(int degree, int count) {
  const KnotVector knots = KnotVector::clamped(degree, count, {0.0, 1.0});
  std::vector<double> result;
  for (int i = 0; i < count; ++i) {
    double sum = 0.0;
    for (int r = 1; r <= degree; ++r) sum += knots[i + r];
    result.push_back(sum / degree);
  }
  result.front() = 0.0;
  result.back() = 1.0;
  return result;
}

KnotVector directionKnots(int degree, int count, bool closed) {
  return closed ? KnotVector::periodic(degree, count, {0.0, 1.0})
                : KnotVector::clamped(degree, count, {0.0, 1.0});
}

/// Two unit vectors completing `axis` (unit) to a right-handed frame (e1, e2, axis).
void completeFrame(const Eigen::Vector3d& axis, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
  e1 = axis.unitOrthogonal();
  e2 = axis.cross(e1);
}

}  // namespace

CircleFit periodicCircleFit(int degree, int count) {
  checkDirection(degree, count, true, "the circle");
  std::vector<Eigen::Vector3d> polygon;
  for (int i = 0; i < count; ++i) {
    polygon.emplace_back(std::cos(kTwoPi * i / count), std::sin(kTwoPi * i / count), 0.0);
  }
  const BSplineCurve curve = BSplineCurve::closed(degree, polygon, 3, {0.0, 1.0});
  // By symmetry every span is alike, and the extremes lie at its ends or middle; sampled densely
  // anyway.
  double low = std::numeric_limits<double>::infinity();
  double high = 0.0;
  const int samples = 4000;
  for (int i = 0; i <= samples; ++i) {
    const double radius = curve.evaluate(static_cast<double>(i) / (samples * count)).norm();
    low = std::min(low, radius);
    high = std::max(high, radius);
  }
  return {2.0 / (low + high), (high - low) / (high + low)};
}

void SurfaceLayout::validate() const {
  checkDirection(degreeU, countU, closedU, "u");
  checkDirection(degreeV, countV, closedV, "v");
}

BSplineSurface planeSheet(const Eigen::Vector3d& origin, const Eigen::Vector3d& edgeU,
                          const Eigen::Vector3d& edgeV, const SurfaceLayout& layout) {
  layout.validate();
  if (layout.closedU || layout.closedV) {
    throw InputError(
        "a plane sheet is open in both directions; drop --closed-u/--closed-v or use "
        "a cylinder or torus");
  }
  if (!origin.allFinite() || !edgeU.allFinite() || !edgeV.allFinite() ||
      !(edgeU.cross(edgeV).norm() > 1e-12 * edgeU.norm() * edgeV.norm())) {
    throw InputError("a plane sheet needs two non-parallel, non-zero edges");
  }
  const std::vector<double> su = greville(layout.degreeU, layout.countU);
  const std::vector<double> sv = greville(layout.degreeV, layout.countV);
  std::vector<Eigen::Vector3d> points;
  for (const double s : su) {
    for (const double t : sv) points.push_back(origin + s * edgeU + t * edgeV);
  }
  return BSplineSurface(directionKnots(layout.degreeU, layout.countU, false),
                        directionKnots(layout.degreeV, layout.countV, false), points);
}

BSplineSurface cylinderSurface(const Eigen::Vector3d& base, const Eigen::Vector3d& axis,
                               double radius, const SurfaceLayout& layout) {
  layout.validate();
  if (layout.closedU == layout.closedV) {
    throw InputError(
        "a cylinder is closed in exactly one direction (--closed-u around the axis, or "
        "--closed-v); use a torus for both and a plane for neither");
  }
  if (!base.allFinite() || !axis.allFinite() || !(axis.norm() > 0.0) || !(radius > 0.0) ||
      !std::isfinite(radius)) {
    throw InputError("a cylinder needs a finite, non-zero axis and a positive radius");
  }
  const bool aroundU = layout.closedU;
  const int degreeAround = aroundU ? layout.degreeU : layout.degreeV;
  const int countAround = aroundU ? layout.countU : layout.countV;
  const int degreeAlong = aroundU ? layout.degreeV : layout.degreeU;
  const int countAlong = aroundU ? layout.countV : layout.countU;
  const double scale = periodicCircleFit(degreeAround, countAround).polygonScale * radius;
  Eigen::Vector3d e1, e2;
  completeFrame(axis.normalized(), e1, e2);
  const std::vector<double> along = greville(degreeAlong, countAlong);
  std::vector<Eigen::Vector3d> points;
  const auto ring = [&](int k) {
    const double angle = kTwoPi * k / countAround;
    return Eigen::Vector3d(scale * (std::cos(angle) * e1 + std::sin(angle) * e2));
  };
  for (int i = 0; i < layout.countU; ++i) {
    for (int j = 0; j < layout.countV; ++j) {
      points.push_back(aroundU ? base + along[static_cast<std::size_t>(j)] * axis + ring(i)
                               : base + along[static_cast<std::size_t>(i)] * axis + ring(j));
    }
  }
  return BSplineSurface(directionKnots(layout.degreeU, layout.countU, layout.closedU),
                        directionKnots(layout.degreeV, layout.countV, layout.closedV), points,
                        layout.closedU, layout.closedV);
}

BSplineSurface torusSurface(const Eigen::Vector3d& center, const Eigen::Vector3d& axis,
                            double majorRadius, double minorRadius, const SurfaceLayout& layout) {
  layout.validate();
  if (!layout.closedU || !layout.closedV) {
    throw InputError("a torus is closed in both directions (--closed-u --closed-v)");
  }
  if (!center.allFinite() || !axis.allFinite() || !(axis.norm() > 0.0) || !(minorRadius > 0.0) ||
      !(minorRadius < majorRadius) || !std::isfinite(majorRadius)) {
    throw InputError("a torus needs a finite, non-zero axis and radii 0 < minor < major");
  }
  const Eigen::Vector3d a = axis.normalized();
  Eigen::Vector3d e1, e2;
  completeFrame(a, e1, e2);
  const double scaleU = periodicCircleFit(layout.degreeU, layout.countU).polygonScale;
  const double scaleV = periodicCircleFit(layout.degreeV, layout.countV).polygonScale * minorRadius;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < layout.countU; ++i) {
    const double angle = kTwoPi * i / layout.countU;
    const Eigen::Vector3d direction = scaleU * (std::cos(angle) * e1 + std::sin(angle) * e2);
    for (int j = 0; j < layout.countV; ++j) {
      const double phi = kTwoPi * j / layout.countV;
      points.push_back(center + (majorRadius + scaleV * std::cos(phi)) * direction +
                       scaleV * std::sin(phi) * a);
    }
  }
  return BSplineSurface(directionKnots(layout.degreeU, layout.countU, true),
                        directionKnots(layout.degreeV, layout.countV, true), points, true, true);
}

namespace {

/// The points' centroid and the eigen-decomposition of their covariance (eigenvalues ascending).
struct PrincipalAxes {
  Eigen::Vector3d center;
  Eigen::Vector3d values;
  Eigen::Matrix3d vectors;
};

/// InputError unless `points` are finite and span a plane (not all equal or on a line).
PrincipalAxes principalAxes(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) center += p;
  center /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) covariance += (p - center) * (p - center).transpose();
  covariance /= static_cast<double>(points.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  const Eigen::Vector3d values = eigen.eigenvalues();  // ascending
  if (!(values[1] > 1e-20 * values[2]) || !(values[2] > 0.0)) {
    throw InputError(
        "the target's points are all equal or on a line: no surface can be placed "
        "around them");
  }
  return {center, values, eigen.eigenvectors()};
}

/// The plane through the points' centre across their smallest principal axis, with the in-plane
/// directions a (largest axis) and b = normal x a.
struct PlaneFrame {
  Eigen::Vector3d center, normal, a, b;

  /// The in-plane direction at `angle` from a towards b.
  Eigen::Vector3d direction(double angle) const {
    return std::cos(angle) * a + std::sin(angle) * b;
  }

  /// The bounding rectangle [low, high] of the points in the coordinates (u, v) =
  /// (direction(angle), normal x u), and its area.
  double rectangle(const std::vector<Eigen::Vector3d>& points, double angle, Eigen::Vector2d& low,
                   Eigen::Vector2d& high) const {
    const Eigen::Vector3d u = direction(angle);
    const Eigen::Vector3d v = normal.cross(u);
    low.setConstant(std::numeric_limits<double>::infinity());
    high.setConstant(-std::numeric_limits<double>::infinity());
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector2d q((p - center).dot(u), (p - center).dot(v));
      low = low.cwiseMin(q);
      high = high.cwiseMax(q);
    }
    return (high - low).prod();
  }

  /// The angle in [0, 90) degrees of the smallest-area bounding rectangle: 1 degree steps, then
  /// 0.01 degree steps around the best.
  double smallestRectangleAngle(const std::vector<Eigen::Vector3d>& points) const {
    Eigen::Vector2d low, high;
    const double degree = kTwoPi / 360.0;
    double bestAngle = 0.0;
    double bestArea = std::numeric_limits<double>::infinity();
    for (int step = 0; step < 90; ++step) {
      const double area = rectangle(points, step * degree, low, high);
      if (area < bestArea) bestArea = area, bestAngle = step * degree;
    }
    const double coarse = bestAngle;
    for (int step = -100; step <= 100; ++step) {
      const double angle = coarse + 0.01 * step * degree;
      const double area = rectangle(points, angle, low, high);
      if (area < bestArea) bestArea = area, bestAngle = angle;
    }
    return bestAngle;
  }
};

/// A plane sheet over the points' smallest bounding rectangle in their best-fitting plane, u
/// along its longer side, scaled by options.scale about its middle.
BSplineSurface planeAround(const std::vector<Eigen::Vector3d>& points, const PrincipalAxes& axes,
                           const InitialSurfaceOptions& options) {
  const Eigen::Vector3d normal = axes.vectors.col(0);
  const Eigen::Vector3d a = axes.vectors.col(2);
  const PlaneFrame frame{axes.center, normal, a, normal.cross(a)};
  const double bestAngle = frame.smallestRectangleAngle(points);
  Eigen::Vector2d low, high;
  frame.rectangle(points, bestAngle, low, high);
  Eigen::Vector3d u = frame.direction(bestAngle);
  Eigen::Vector3d v = normal.cross(u);
  Eigen::Vector2d size = high - low;
  const Eigen::Vector2d middle = 0.5 * (low + high);
  if (size.y() > size.x()) {  // u along the longer side, keeping u x v = normal
    const Eigen::Vector3d swap = u;
    u = v;
    v = -swap;
    size = Eigen::Vector2d(size.y(), size.x());
  }
  const Eigen::Vector3d middlePoint = axes.center + middle.x() * frame.direction(bestAngle) +
                                      middle.y() * normal.cross(frame.direction(bestAngle));
  const Eigen::Vector3d edgeU = options.scale * size.x() * u;
  const Eigen::Vector3d edgeV = options.scale * size.y() * v;
  return planeSheet(middlePoint - 0.5 * edgeU - 0.5 * edgeV, edgeU, edgeV, options.layout);
}

/// The symmetry axis of a cylinder or torus (unit): options.axis, else the principal axis whose
/// eigenvalue stands apart from the other two.
Eigen::Vector3d symmetryAxis(const PrincipalAxes& axes, const InitialSurfaceOptions& options) {
  if (options.axis) {
    if (!options.axis->allFinite() || !(options.axis->norm() > 0.0)) {
      throw InputError("the initial surface's axis must be a finite, non-zero vector");
    }
    return options.axis->normalized();
  }
  const Eigen::Vector3d& values = axes.values;
  return values[1] - values[0] > values[2] - values[1] ? axes.vectors.col(0) : axes.vectors.col(2);
}

/// The cylinder around `axis` through `center` over the points' extent along it, of their mean
/// distance from it times options.scale.
BSplineSurface cylinderAround(const std::vector<Eigen::Vector3d>& points,
                              const Eigen::Vector3d& center, const Eigen::Vector3d& axis,
                              const InitialSurfaceOptions& options) {
  double radius = 0.0;
  double low = std::numeric_limits<double>::infinity();
  double high = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : points) {
    const double along = (p - center).dot(axis);
    radius += (p - center - along * axis).norm();
    low = std::min(low, along);
    high = std::max(high, along);
  }
  radius /= static_cast<double>(points.size());
  if (!(high > low) || !(radius > 0.0)) {
    throw InputError(
        "the target's points give no cylinder: they have no extent along the axis "
        "or lie on it");
  }
  return cylinderSurface(center + low * axis, (high - low) * axis, options.scale * radius,
                         options.layout);
}

/// The torus around `axis` through `center`: major radius the points' mean distance from the
/// axis, minor radius their RMS distance from that circle times options.scale.
BSplineSurface torusAround(const std::vector<Eigen::Vector3d>& points,
                           const Eigen::Vector3d& center, const Eigen::Vector3d& axis,
                           const InitialSurfaceOptions& options) {
  double major = 0.0;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d offset = p - center;
    major += (offset - offset.dot(axis) * axis).norm();
  }
  major /= static_cast<double>(points.size());
  double minor = 0.0;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d offset = p - center;
    const double height = offset.dot(axis);
    const double radial = (offset - height * axis).norm() - major;
    minor += radial * radial + height * height;
  }
  minor = options.scale * std::sqrt(minor / static_cast<double>(points.size()));
  if (!(minor > 0.0) || !(minor < major)) {
    throw InputError("the target's points give no ring torus around the axis (minor radius " +
                     std::to_string(minor) + ", major " + std::to_string(major) + ")");
  }
  return torusSurface(center, axis, major, minor, options.layout);
}

}  // namespace

BSplineSurface initialSurfaceAround(const std::vector<Eigen::Vector3d>& points,
                                    const InitialSurfaceOptions& options) {
  if (points.empty()) throw InputError("no points to place an initial surface around");
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!points[k].allFinite()) {
      throw InputError("point " + std::to_string(k) + " has a non-finite coordinate");
    }
  }
  if (!(options.scale > 0.0) || !std::isfinite(options.scale)) {
    throw InputError("the initial surface's scale must be positive");
  }
  options.layout.validate();
  const PrincipalAxes axes = principalAxes(points);
  if (options.shape == InitialSurfaceShape::Plane) return planeAround(points, axes, options);
  const Eigen::Vector3d axis = symmetryAxis(axes, options);
  if (options.shape == InitialSurfaceShape::Cylinder) {
    return cylinderAround(points, axes.center, axis, options);
  }
  return torusAround(points, axes.center, axis, options);
}

}  // namespace d2vdb
