#include "d2vdb/spline/BezierCurve.h"

#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/spline/detail/BernsteinAlgorithms.h"

namespace d2vdb {
namespace {

const BezierCurve::ControlPoints& requireValid(const BezierCurve::ControlPoints& points) {
  if (points.cols() < 1)
    throw InputError("Bézier curve: no control points given (expected 1 to " +
                     std::to_string(kMaxBernsteinDegree + 1) + ")");
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    if (!points.col(i).allFinite()) {
      throw InputError("Bézier curve: control point " + std::to_string(i) + " " +
                       formatPoint(points.col(i)) + " is not finite");
    }
  }
  return points;
}

BezierCurve::ControlPoints toMatrix(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty() || points.size() > static_cast<std::size_t>(kMaxBernsteinDegree + 1)) {
    throw InputError("Bézier curve: " + std::to_string(points.size()) +
                     " control points given (expected 1 to " +
                     std::to_string(kMaxBernsteinDegree + 1) + ")");
  }
  BezierCurve::ControlPoints matrix(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    matrix.col(static_cast<Eigen::Index>(i)) = points[i];
  }
  return matrix;
}

}  // namespace

BezierCurve::BezierCurve(const std::vector<Eigen::Vector3d>& controlPoints)
    : controlPoints_(requireValid(toMatrix(controlPoints))) {}

BezierCurve::BezierCurve(const ControlPoints& controlPoints)
    : controlPoints_(requireValid(controlPoints)) {}

Eigen::Vector3d BezierCurve::evaluate(double t) const {
  return detail::deCasteljauEvaluate<3>(controlPoints_, t);
}

BezierCurve BezierCurve::derivative() const {
  return BezierCurve(Unchecked{}, detail::differentiate<3>(controlPoints_));
}

std::pair<BezierCurve, BezierCurve> BezierCurve::subdivide(double t) const {
  ControlPoints left;
  ControlPoints right;
  detail::deCasteljauSplit<3>(controlPoints_, t, left, right);
  return {BezierCurve(Unchecked{}, left), BezierCurve(Unchecked{}, right)};
}

BezierCurve BezierCurve::restricted(double a, double b) const {
  if (!std::isfinite(a) || !std::isfinite(b) || a == b) {
    throw InputError("Bézier curve: cannot restrict to [" + formatNumber(a) + ", " +
                     formatNumber(b) + "] (expected finite a != b)");
  }
  return BezierCurve(Unchecked{}, detail::restrictTo<3>(controlPoints_, a, b));
}

BezierCurve BezierCurve::elevated(int times) const {
  if (times < 0 || degree() + times > kMaxBernsteinDegree) {
    throw InputError("Bézier curve: cannot elevate degree " + std::to_string(degree()) + " by " +
                     std::to_string(times) + " (the result must be at most degree " +
                     std::to_string(kMaxBernsteinDegree) + ")");
  }
  ControlPoints result = controlPoints_;
  for (int i = 0; i < times; ++i) result = detail::elevateOnce<3>(result);
  return BezierCurve(Unchecked{}, result);
}

BezierCurve BezierCurve::translated(const Eigen::Vector3d& offset) const {
  if (!offset.allFinite()) throw InputError("Bézier curve: translation offset is not finite");
  ControlPoints result = controlPoints_;
  result.colwise() += offset;
  return BezierCurve(Unchecked{}, result);
}

BernsteinPolynomial BezierCurve::coordinate(int axis) const {
  if (axis < 0 || axis > 2) {
    throw InputError("Bézier curve: axis " + std::to_string(axis) +
                     " does not exist (expected 0, 1 or 2)");
  }
  return BernsteinPolynomial(BernsteinPolynomial::Coefficients(controlPoints_.row(axis)));
}

Eigen::AlignedBox3d BezierCurve::controlPointBounds() const {
  return Eigen::AlignedBox3d(controlPoints_.rowwise().minCoeff(),
                             controlPoints_.rowwise().maxCoeff());
}

BernsteinPolynomial dot(const BezierCurve& a, const BezierCurve& b) {
  if (a.degree() + b.degree() > kMaxBernsteinDegree) {
    throw InputError("Bézier curve: the dot product of degrees " + std::to_string(a.degree()) +
                     " and " + std::to_string(b.degree()) + " exceeds degree " +
                     std::to_string(kMaxBernsteinDegree));
  }
  return BernsteinPolynomial(detail::productCoefficients<3>(a.controlPoints(), b.controlPoints()));
}

}  // namespace d2vdb
