// The approximant of an analytic surface built from its exact closest point, shared by the field
// and fitting tests as an independent reference.
#pragma once

#include <Eigen/Core>

#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Approximant.h"

namespace d2vdb::test {

/// Approximant of an analytic surface at `point` from its exact closest point `s` and the
/// surface's differential geometry there (AnalyticShapes' closestSurfacePoint()).
inline Approximant approximantFrom(const SurfacePoint& s, const Eigen::Vector3d& point) {
  Approximant a;
  a.kind = TargetKind::Surface;
  a.origin = point;
  a.footpoint = s.point;
  a.normal = s.normal;
  a.tangent = s.e1;
  a.k1 = s.k1;
  a.k2 = s.k2;
  a.distance = s.signedDistance;
  return a;
}

}  // namespace d2vdb::test
