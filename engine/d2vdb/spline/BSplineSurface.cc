#include "d2vdb/spline/BSplineSurface.h"

#include <cmath>
#include <string>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb {
namespace {

// The knot vector one surface direction keeps (see BSplineCurve's equivalent): closed directions
// must be uniform periodic and keep the exact periodic vector.
KnotVector checkedDirection(KnotVector knots, bool closed, const char* name) {
  if (!closed) return knots;
  const int p = knots.degree();
  const int unique = knots.basisFunctionCount() - p;
  if (unique < p + 1 || !knots.isUniformPeriodic()) {
    throw InputError(std::string("B-spline surface: the ") + name +
                     " knots of a closed direction must be uniform periodic (equally spaced, "
                     "unique control points + 2 degree + 1 of them, with at least degree + 1 "
                     "unique control points), but they are not");
  }
  return KnotVector::periodic(p, unique, knots.domain());
}

int storedCount(const KnotVector& knots, bool closed) {
  return closed ? knots.basisFunctionCount() - knots.degree() : knots.basisFunctionCount();
}

void requireFinite(const std::vector<Eigen::Vector3d>& points, int countV) {
  for (std::size_t index = 0; index < points.size(); ++index) {
    if (!points[index].allFinite()) {
      const int i = static_cast<int>(index) / countV;
      const int j = static_cast<int>(index) % countV;
      throw InputError("B-spline surface: control point [" + std::to_string(i) + "][" +
                       std::to_string(j) + "] " + formatPoint(points[index]) + " is not finite");
    }
  }
}

double parameterInDomain(const KnotVector& knots, bool closed, double t, const char* name) {
  if (!closed) return t;
  if (!std::isfinite(t)) {
    throw InputError(std::string("B-spline surface: parameter ") + name + " = " + formatNumber(t) +
                     " is not finite");
  }
  return knots.domain().wrap(t);
}

}  // namespace

BSplineSurface::BSplineSurface(KnotVector knotsU, KnotVector knotsV,
                               std::vector<Eigen::Vector3d> controlPoints, bool closedU,
                               bool closedV)
    : knotsU_(checkedDirection(std::move(knotsU), closedU, "u")),
      knotsV_(checkedDirection(std::move(knotsV), closedV, "v")),
      controlPoints_(std::move(controlPoints)),
      countU_(storedCount(knotsU_, closedU)),
      countV_(storedCount(knotsV_, closedV)),
      closedU_(closedU),
      closedV_(closedV) {
  const std::size_t expected =
      static_cast<std::size_t>(countU_) * static_cast<std::size_t>(countV_);
  if (controlPoints_.size() != expected) {
    throw InputError("B-spline surface: " + std::to_string(controlPoints_.size()) +
                     " control points given, but the knot vectors need a " +
                     std::to_string(countU_) + " x " + std::to_string(countV_) + " grid (" +
                     std::to_string(expected) + " points)");
  }
  requireFinite(controlPoints_, countV_);
}

BSplineSurface BSplineSurface::clamped(int degreeU, int degreeV, int countU, int countV,
                                       std::vector<Eigen::Vector3d> controlPoints,
                                       ParameterInterval domainU, ParameterInterval domainV) {
  return BSplineSurface(KnotVector::clamped(degreeU, countU, domainU),
                        KnotVector::clamped(degreeV, countV, domainV), std::move(controlPoints));
}

void BSplineSurface::setControlPoints(std::vector<Eigen::Vector3d> controlPoints) {
  if (controlPoints.size() != controlPoints_.size()) {
    throw InputError("B-spline surface: " + std::to_string(controlPoints.size()) +
                     " new control points given, expected " +
                     std::to_string(controlPoints_.size()));
  }
  requireFinite(controlPoints, countV_);
  controlPoints_ = std::move(controlPoints);
}

Eigen::Vector3d BSplineSurface::evaluate(double u, double v) const {
  const double uu = parameterInDomain(knotsU_, closedU_, u, "u");
  const double vv = parameterInDomain(knotsV_, closedV_, v, "v");
  return evaluateInSpans(knotsU_.findSpan(uu), knotsV_.findSpan(vv), uu, vv);
}

Eigen::Vector3d BSplineSurface::evaluateInSpans(int spanU, int spanV, double u, double v) const {
  const BasisValues basisU = basisValues(knotsU_, spanU, u);
  const BasisValues basisV = basisValues(knotsV_, spanV, v);
  const int firstU = spanU - degreeU();
  const int firstV = spanV - degreeV();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  for (int a = 0; a <= degreeU(); ++a) {
    Eigen::Vector3d row = Eigen::Vector3d::Zero();
    for (int b = 0; b <= degreeV(); ++b) {
      row += basisV[b] * controlPoints_[controlPointIndex(firstU + a, firstV + b)];
    }
    point += basisU[a] * row;
  }
  return point;
}

SurfaceDerivatives BSplineSurface::derivatives(double u, double v) const {
  const double uu = parameterInDomain(knotsU_, closedU_, u, "u");
  const double vv = parameterInDomain(knotsV_, closedV_, v, "v");
  return derivativesInSpans(knotsU_.findSpan(uu), knotsV_.findSpan(vv), uu, vv);
}

SurfaceDerivatives BSplineSurface::derivativesInSpans(int spanU, int spanV, double u,
                                                      double v) const {
  const BasisDerivatives basisU = basisDerivatives(knotsU_, spanU, u, 2);
  const BasisDerivatives basisV = basisDerivatives(knotsV_, spanV, v, 2);
  const int firstU = spanU - degreeU();
  const int firstV = spanV - degreeV();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  SurfaceDerivatives result{zero, zero, zero, zero, zero, zero};
  for (int a = 0; a <= degreeU(); ++a) {
    // Row sums over v of the v-basis and its first two derivatives.
    Eigen::Vector3d row = zero;
    Eigen::Vector3d rowV = zero;
    Eigen::Vector3d rowVV = zero;
    for (int b = 0; b <= degreeV(); ++b) {
      const Eigen::Vector3d& point = controlPoints_[controlPointIndex(firstU + a, firstV + b)];
      row += basisV(0, b) * point;
      rowV += basisV(1, b) * point;
      rowVV += basisV(2, b) * point;
    }
    result.point += basisU(0, a) * row;
    result.du += basisU(1, a) * row;
    result.duu += basisU(2, a) * row;
    result.dv += basisU(0, a) * rowV;
    result.duv += basisU(1, a) * rowV;
    result.dvv += basisU(0, a) * rowVV;
  }
  return result;
}

std::vector<Eigen::Vector3d> BSplineSurface::sample(int samplesU, int samplesV) const {
  if (samplesU < 2 || samplesV < 2) {
    throw InputError("B-spline surface: cannot sample a " + std::to_string(samplesU) + " x " +
                     std::to_string(samplesV) + " grid (expected at least 2 x 2)");
  }
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<std::size_t>(samplesU) * static_cast<std::size_t>(samplesV));
  for (int i = 0; i < samplesU; ++i) {
    const double u = domainU().at(static_cast<double>(i) / (samplesU - 1));
    for (int j = 0; j < samplesV; ++j) {
      points.push_back(evaluate(u, domainV().at(static_cast<double>(j) / (samplesV - 1))));
    }
  }
  return points;
}

}  // namespace d2vdb
