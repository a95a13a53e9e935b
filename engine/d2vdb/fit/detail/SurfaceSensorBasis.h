// Internal: the linear map from a B-spline surface's control points to the positions of its
// sensors.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/fit/detail/SensorMap.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb::detail {

/// Sensors of a surface at fixed parameter pairs (u, v) and the tensor-product basis there:
/// sensor k lies at x_k = sum_{a,b} N_a(u_k) M_b(v_k) P[index(k, a (q + 1) + b)], with P the
/// surface's stored control points (closed directions wrap through
/// BSplineSurface::controlPointIndex). Groups (SensorMap) are the knot cells: sensors in the same
/// cell share their (p + 1)(q + 1) control points. Immutable.
class SurfaceSensorBasis final : public SensorMap {
 public:
  /// Evaluates the basis at `parameters` ((u, v) pairs in the surface's domain; closed directions
  /// wrap), in parallel. Throws InputError for a parameter outside an open direction's domain or
  /// a non-finite parameter (naming the first such sensor).
  SurfaceSensorBasis(const BSplineSurface& surface, std::vector<Eigen::Vector2d> parameters);

  /// Parameters (u, v) of sensor k (wrapped into the domain).
  const Eigen::Vector2d& parameter(int k) const { return parameters_[static_cast<std::size_t>(k)]; }
  /// All sensor parameters.
  const std::vector<Eigen::Vector2d>& parameters() const { return parameters_; }

 private:
  std::vector<Eigen::Vector2d> parameters_;
};

/// Sensor parameters on a tensor grid: in each direction `perSpan` >= 1 values per non-empty knot
/// span, at the midpoints of perSpan equal parts of the span, plus both domain ends when the
/// direction is open (so that the surface's boundary is held too); all pairs of the two lists,
/// u-major, ascending. InputError for perSpan < 1.
std::vector<Eigen::Vector2d> uniformSurfaceSensorParameters(const BSplineSurface& surface,
                                                            int perSpan);

}  // namespace d2vdb::detail
