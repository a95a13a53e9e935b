#include "d2vdb/spline/BSplineCurve.h"

#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb {
namespace {

void requireValidControlPoints(const std::vector<Eigen::Vector3d>& points, int dimension) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw InputError("B-spline curve: control point " + std::to_string(i) + " " +
                       formatPoint(points[i]) + " is not finite");
    }
    if (dimension == 2 && points[i].z() != 0.0) {
      throw InputError("B-spline curve: control point " + std::to_string(i) + " " +
                       formatPoint(points[i]) + " has z != 0, but a 2D curve must have z = 0");
    }
  }
}

// The knot vector a curve keeps: open curves keep theirs; closed curves check periodicity and
// keep the exact uniform periodic vector on the same domain.
KnotVector checkedKnots(KnotVector knots, std::size_t controlPointCount, int dimension,
                        bool closed) {
  if (dimension != 2 && dimension != 3) {
    throw InputError("B-spline curve: dimension " + std::to_string(dimension) +
                     " is not supported (expected 2 or 3)");
  }
  const int p = knots.degree();
  const int count = static_cast<int>(controlPointCount);
  if (!closed) {
    if (count != knots.basisFunctionCount()) {
      throw InputError("B-spline curve: " + std::to_string(count) + " control points but the " +
                       std::to_string(knots.size()) + " knots of degree " + std::to_string(p) +
                       " need " + std::to_string(knots.basisFunctionCount()) +
                       " (knots = control points + degree + 1)");
    }
    return knots;
  }
  if (count < p + 1) {
    throw InputError("B-spline curve: a closed curve of degree " + std::to_string(p) +
                     " needs at least " + std::to_string(p + 1) + " unique control points, got " +
                     std::to_string(count));
  }
  if (knots.basisFunctionCount() != count + p) {
    throw InputError("B-spline curve: a closed curve with " + std::to_string(count) +
                     " unique control points of degree " + std::to_string(p) + " needs " +
                     std::to_string(count + 2 * p + 1) +
                     " knots (unique control points + 2 degree + 1), got " +
                     std::to_string(knots.size()));
  }
  if (!knots.isUniformPeriodic()) {
    throw InputError(
        "B-spline curve: the knots of a closed curve must be uniform periodic (equally spaced, " +
        std::to_string(count + 2 * p + 1) + " knots), but they are not");
  }
  return KnotVector::periodic(p, count, knots.domain());
}

}  // namespace

BSplineCurve::BSplineCurve(KnotVector knots, std::vector<Eigen::Vector3d> controlPoints,
                           int dimension, bool closed)
    : knots_(checkedKnots(std::move(knots), controlPoints.size(), dimension, closed)),
      controlPoints_(std::move(controlPoints)),
      dimension_(dimension),
      closed_(closed) {
  requireValidControlPoints(controlPoints_, dimension_);
}

BSplineCurve BSplineCurve::clamped(int degree, std::vector<Eigen::Vector3d> controlPoints,
                                   int dimension, ParameterInterval domain) {
  KnotVector knots = KnotVector::clamped(degree, static_cast<int>(controlPoints.size()), domain);
  return BSplineCurve(std::move(knots), std::move(controlPoints), dimension, false);
}

BSplineCurve BSplineCurve::closed(int degree, std::vector<Eigen::Vector3d> uniqueControlPoints,
                                  int dimension, ParameterInterval domain) {
  KnotVector knots =
      KnotVector::periodic(degree, static_cast<int>(uniqueControlPoints.size()), domain);
  return BSplineCurve(std::move(knots), std::move(uniqueControlPoints), dimension, true);
}

void BSplineCurve::setControlPoints(std::vector<Eigen::Vector3d> controlPoints) {
  if (controlPoints.size() != controlPoints_.size()) {
    throw InputError("B-spline curve: " + std::to_string(controlPoints.size()) +
                     " new control points given, expected " +
                     std::to_string(controlPoints_.size()));
  }
  requireValidControlPoints(controlPoints, dimension_);
  controlPoints_ = std::move(controlPoints);
}

double BSplineCurve::parameterInDomain(double t) const {
  if (!closed_) return t;
  if (!std::isfinite(t)) {
    throw InputError("B-spline curve: parameter " + formatNumber(t) + " is not finite");
  }
  return domain().wrap(t);
}

Eigen::Vector3d BSplineCurve::evaluate(double t) const {
  const double u = parameterInDomain(t);
  const int span = knots_.findSpan(u);
  const BasisValues basis = basisValues(knots_, span, u);
  const int first = span - degree();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  for (int j = 0; j <= degree(); ++j) {
    point += basis[j] * controlPoints_[controlPointIndex(first + j)];
  }
  return point;
}

CurveDerivatives BSplineCurve::derivatives(double t) const {
  const double u = parameterInDomain(t);
  const int span = knots_.findSpan(u);
  const BasisDerivatives basis = basisDerivatives(knots_, span, u, 2);
  const int first = span - degree();
  CurveDerivatives result{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                          Eigen::Vector3d::Zero()};
  for (int j = 0; j <= degree(); ++j) {
    const Eigen::Vector3d& point = controlPoints_[controlPointIndex(first + j)];
    result.point += basis(0, j) * point;
    result.first += basis(1, j) * point;
    result.second += basis(2, j) * point;
  }
  return result;
}

Eigen::Vector3d BSplineCurve::derivative(double t, int order) const {
  const double u = parameterInDomain(t);
  const int span = knots_.findSpan(u);
  const BasisDerivatives basis = basisDerivatives(knots_, span, u, order);
  const int first = span - degree();
  Eigen::Vector3d result = Eigen::Vector3d::Zero();
  for (int j = 0; j <= degree(); ++j) {
    result += basis(order, j) * controlPoints_[controlPointIndex(first + j)];
  }
  return result;
}

std::vector<Eigen::Vector3d> BSplineCurve::sample(int count) const {
  if (count < 2) {
    throw InputError("B-spline curve: cannot sample " + std::to_string(count) +
                     " points (expected at least 2)");
  }
  std::vector<Eigen::Vector3d> points;
  points.reserve(count);
  const ParameterInterval interval = domain();
  for (int i = 0; i < count; ++i) {
    points.push_back(evaluate(interval.at(static_cast<double>(i) / (count - 1))));
  }
  return points;
}

BSplineCurve BSplineCurve::openRepresentation() const {
  if (!closed_) return *this;
  std::vector<Eigen::Vector3d> wrapped = controlPoints_;
  for (int i = 0; i < degree(); ++i) wrapped.push_back(controlPoints_[i]);
  return BSplineCurve(knots_, std::move(wrapped), dimension_, false);
}

void BSplineCurve::insertKnot(double t, int times) {
  const int p = degree();
  const ParameterInterval interval = domain();
  if (times < 1) {
    throw InputError("B-spline curve: cannot insert a knot " + std::to_string(times) +
                     " times (expected at least 1)");
  }
  if (!interval.contains(t)) {
    throw InputError("B-spline curve: cannot insert knot " + formatNumber(t) +
                     " outside the domain [" + formatNumber(interval.start) + ", " +
                     formatNumber(interval.end) + "]");
  }
  const bool interior = t > interval.start && t < interval.end;
  const int allowed = interior ? p : p + 1;
  const int existing = knots_.multiplicity(t);
  if (existing + times > allowed) {
    throw InputError("B-spline curve: inserting knot " + formatNumber(t) + " " +
                     std::to_string(times) + " times would raise its multiplicity from " +
                     std::to_string(existing) + " to " + std::to_string(existing + times) +
                     "; at most " + std::to_string(allowed) + " is allowed " +
                     (interior ? "inside the domain" : "at a domain end"));
  }

  const BSplineCurve open = openRepresentation();
  KnotVector knots = open.knots_;
  std::vector<Eigen::Vector3d> points = open.controlPoints_;
  for (int r = 0; r < times; ++r) {
    // Boehm: with t in [t_s, t_{s+1}], the new points are Q_i = P_i for i <= s - p,
    // Q_i = a_i P_i + (1 - a_i) P_{i-1} with a_i = (t - t_i) / (t_{i+p} - t_i) for
    // s - p < i <= s, and Q_i = P_{i-1} for i > s. The denominators exceed t_{s+1} - t_s > 0.
    const int span = knots.findSpan(t);
    std::vector<Eigen::Vector3d> inserted(points.size() + 1);
    for (int i = 0; i <= span - p; ++i) inserted[i] = points[i];
    for (int i = span - p + 1; i <= span; ++i) {
      const double alpha = (t - knots[i]) / (knots[i + p] - knots[i]);
      inserted[i] = alpha * points[i] + (1.0 - alpha) * points[i - 1];
    }
    for (std::size_t i = span + 1; i < inserted.size(); ++i) {
      inserted[i] = points[i - 1];
    }
    std::vector<double> values = knots.values();
    values.insert(values.begin() + span + 1, t);
    knots = KnotVector(p, std::move(values));
    points = std::move(inserted);
  }
  *this = BSplineCurve(std::move(knots), std::move(points), dimension_, false);
}

std::vector<BezierSegment> BSplineCurve::toBezierSegments() const {
  const int p = degree();
  const KnotVector& k = knots_;
  std::vector<BezierSegment> segments;
  for (int span = p; span < k.basisFunctionCount(); ++span) {
    const double a = k[span];
    const double b = k[span + 1];
    if (!(a < b)) continue;
    BezierCurve::ControlPoints bezier(3, p + 1);
    for (int c = 0; c <= p; ++c) {
      // Blossom C(x_1..x_p) with x_1..x_{p-c} = a, the rest b, by de Boor's recurrence on the
      // span's p + 1 control points d_j = P_{span-p+j}, level r using argument x_r.
      std::array<Eigen::Vector3d, kMaxSplineDegree + 1> d;
      for (int j = 0; j <= p; ++j) {
        d[j] = controlPoints_[controlPointIndex(span - p + j)];
      }
      for (int r = 1; r <= p; ++r) {
        const double x = r <= p - c ? a : b;
        for (int j = p; j >= r; --j) {
          const double left = k[span - p + j];
          const double alpha = (x - left) / (k[span + j - r + 1] - left);
          d[j] = (1.0 - alpha) * d[j - 1] + alpha * d[j];
        }
      }
      bezier.col(c) = d[p];
    }
    segments.push_back(BezierSegment{BezierCurve(bezier), ParameterInterval{a, b}});
  }
  return segments;
}

}  // namespace d2vdb
