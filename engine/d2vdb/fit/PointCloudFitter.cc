#include "d2vdb/fit/PointCloudFitter.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/fit/detail/CurveFitLoop.h"
#include "d2vdb/fit/detail/PointCloudProblem.h"
#include "d2vdb/fit/detail/SplineFit.h"

namespace d2vdb {

Approximant curveApproximantAt(const BSplineCurve& curve, double t,
                               const Eigen::Vector3d& dataPoint) {
  const ParameterInterval domain = curve.domain();
  const bool endPoint = !curve.isClosed() && (t <= domain.start || t >= domain.end);
  return detail::curveApproximantFrom(curve.derivatives(t), endPoint, curve.dimension(), dataPoint);
}

CurveFitResult fitCurveToPoints(const BSplineCurve& initial,
                                const std::vector<Eigen::Vector3d>& points,
                                const CurveFitOptions& options) {
  detail::requireDataPoints(points, "a curve", initial.dimension() == 2);
  if (static_cast<std::size_t>(initial.controlPointCount()) > points.size()) {
    // Each data point gives one equation (its distance to the curve): fewer cannot determine the
    // control points, and the work would be spent on nothing the data says.
    throw InputError("the curve has " + std::to_string(initial.controlPointCount()) +
                     " control points but the point cloud only " + std::to_string(points.size()) +
                     " points, which cannot determine them; use at most " +
                     std::to_string(points.size()) + " control points");
  }
  detail::validateCurveFit(initial, options);
  detail::PointCloudProblem problem(initial, points, options);
  return detail::runCurveFit(initial, options, problem);
}

}  // namespace d2vdb
