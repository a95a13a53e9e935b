#include "d2vdb/fit/InitialCurve.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/fit/detail/QuadraticModel.h"
#include "d2vdb/fit/detail/SensorBasis.h"
#include "d2vdb/fit/detail/SmoothingMatrix.h"
#include "d2vdb/spline/KnotVector.h"

namespace d2vdb {
namespace {

void checkCommon(const std::vector<Eigen::Vector3d>& points, int degree, int controlPoints,
                 int dimension) {
  if (points.empty()) throw InputError("no points to build an initial curve from");
  if (dimension != 2 && dimension != 3) {
    throw InputError("curve dimension must be 2 or 3, got " + std::to_string(dimension));
  }
  if (degree < 1 || degree > kMaxSplineDegree) {
    throw InputError("curve degree must be 1.." + std::to_string(kMaxSplineDegree) + ", got " +
                     std::to_string(degree));
  }
  if (controlPoints < degree + 1) {
    throw InputError("a degree-" + std::to_string(degree) + " curve needs at least " +
                     std::to_string(degree + 1) + " control points, got " +
                     std::to_string(controlPoints));
  }
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!points[k].allFinite()) {
      throw InputError("point " + std::to_string(k) + " has a non-finite coordinate");
    }
  }
}

std::vector<Eigen::Vector3d> flattened(const std::vector<Eigen::Vector3d>& points, int dimension) {
  std::vector<Eigen::Vector3d> result = points;
  if (dimension == 2) {
    for (Eigen::Vector3d& p : result) p.z() = 0.0;
  }
  return result;
}

}  // namespace

BSplineCurve fitPolylineLeastSquares(const std::vector<Eigen::Vector3d>& input, bool closed,
                                     int degree, int controlPoints, int dimension) {
  checkCommon(input, degree, controlPoints, dimension);
  const std::vector<Eigen::Vector3d> points = flattened(input, dimension);
  std::vector<double> cumulative(points.size(), 0.0);
  for (std::size_t i = 1; i < points.size(); ++i) {
    cumulative[i] = cumulative[i - 1] + (points[i] - points[i - 1]).norm();
  }
  const double total = cumulative.back() + (closed ? (points.front() - points.back()).norm() : 0.0);
  if (!(total > 0.0)) {
    throw InputError("all points coincide: no curve can be fitted through them");
  }
  std::vector<double> parameters(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    parameters[i] = std::min(cumulative[i] / total, closed ? std::nextafter(1.0, 0.0) : 1.0);
  }
  // Start: control points spread along the polyline (used only as the expansion point of the
  // quadratic model, whose minimiser does not depend on it).
  std::vector<Eigen::Vector3d> start(static_cast<std::size_t>(controlPoints));
  for (int i = 0; i < controlPoints; ++i) {
    const double s = closed ? static_cast<double>(i) / controlPoints
                            : static_cast<double>(i) / (controlPoints - 1);
    const auto found = std::lower_bound(parameters.begin(), parameters.end(), s);
    start[static_cast<std::size_t>(i)] = points[static_cast<std::size_t>(std::min<std::ptrdiff_t>(
        found - parameters.begin(), static_cast<std::ptrdiff_t>(points.size()) - 1))];
  }
  BSplineCurve curve = closed ? BSplineCurve::closed(degree, start, dimension)
                              : BSplineCurve::clamped(degree, start, dimension);
  const detail::SensorBasis basis(curve, parameters);
  std::vector<QuadraticForm> forms(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    forms[i].A = Eigen::Matrix3d::Identity();
    forms[i].b = points[i];
    forms[i].c = points[i].squaredNorm();
  }
  Eigen::SparseMatrix<double> smoothing(controlPoints, controlPoints);
  if (degree >= 2) smoothing = 1e-9 * detail::derivativeGramMatrix(curve, 2);
  detail::QuadraticModel model(controlPoints, dimension, std::move(smoothing));
  const std::vector<Eigen::Vector3d> step = model.solve(basis, forms, start, 0.0);
  std::vector<Eigen::Vector3d> fitted(start.size());
  for (std::size_t i = 0; i < start.size(); ++i) fitted[i] = start[i] + step[i];
  curve.setControlPoints(fitted);
  return curve;
}

BSplineCurve initialCurveAround(const std::vector<Eigen::Vector3d>& input, InitialShape shape,
                                int degree, int controlPoints, int dimension, double scale) {
  checkCommon(input, degree, controlPoints, dimension);
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    throw InputError("the size factor of the initial curve must be positive");
  }
  const std::vector<Eigen::Vector3d> points = flattened(input, dimension);
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) center += p;
  center /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) covariance += (p - center) * (p - center).transpose();
  Eigen::Vector3d axis1 = Eigen::Vector3d::UnitX();
  Eigen::Vector3d axis2 = Eigen::Vector3d::UnitY();
  if (dimension == 2) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(covariance.topLeftCorner<2, 2>());
    axis1.head<2>() = solver.eigenvectors().col(1);
    axis2.head<2>() = solver.eigenvectors().col(0);
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    axis1 = solver.eigenvectors().col(2);
    axis2 = solver.eigenvectors().col(1);
  }
  double extent1 = 0.0;
  double extent2 = 0.0;
  for (const Eigen::Vector3d& p : points) {
    extent1 = std::max(extent1, std::abs((p - center).dot(axis1)));
    extent2 = std::max(extent2, std::abs((p - center).dot(axis2)));
  }
  if (!(extent1 > 0.0)) {
    throw InputError("all points coincide: no initial curve can be placed around them");
  }
  if (shape == InitialShape::Circle) extent2 = extent1;
  extent2 = std::max(extent2, 0.1 * extent1);
  const int samples = 16 * controlPoints;
  std::vector<Eigen::Vector3d> ellipse(static_cast<std::size_t>(samples));
  const double twoPi = 6.283185307179586476925;
  for (int i = 0; i < samples; ++i) {
    const double angle = twoPi * i / samples;
    ellipse[static_cast<std::size_t>(i)] = center + scale * extent1 * std::cos(angle) * axis1 +
                                           scale * extent2 * std::sin(angle) * axis2;
  }
  return fitPolylineLeastSquares(ellipse, true, degree, controlPoints, dimension);
}

}  // namespace d2vdb
