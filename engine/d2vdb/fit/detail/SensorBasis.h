// Internal: the linear map from a B-spline curve's control points to the positions of its sensors.
#pragma once

#include <vector>

#include "d2vdb/fit/detail/SensorMap.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb::detail {

/// Sensors of a curve at fixed parameter values and the B-spline basis there: sensor k lies at
/// x_k = sum_j weight(k, j) P[index(k, j)], j = 0..p, with P the curve's stored control points
/// (closed curves wrap through BSplineCurve::controlPointIndex). Groups (SensorMap) are the knot
/// spans. Immutable.
class SensorBasis final : public SensorMap {
 public:
  /// Evaluates the basis at `parameters` (each in the curve's domain; closed curves wrap), in
  /// parallel. Throws InputError for a parameter outside an open curve's domain or NaN.
  SensorBasis(const BSplineCurve& curve, std::vector<double> parameters);

  /// Parameter of sensor k.
  double parameter(int k) const { return parameters_[static_cast<std::size_t>(k)]; }
  /// All sensor parameters.
  const std::vector<double>& parameters() const { return parameters_; }

 private:
  std::vector<double> parameters_;
};

/// Parameters of `perSpan` >= 1 sensors in every non-empty knot span of the curve's domain, at
/// the midpoints of perSpan equal parts of the span, plus both domain ends for an open curve (so
/// that its ends are held too), ascending. InputError for perSpan < 1.
std::vector<double> uniformSensorParameters(const BSplineCurve& curve, int perSpan);

}  // namespace d2vdb::detail
