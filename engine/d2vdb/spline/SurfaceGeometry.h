// Differential geometry of a parametric surface at one point: unit normal, principal curvatures and
// directions from the first and second fundamental forms.
#pragma once

#include <Eigen/Core>

#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// The principal frame of a surface at one parameter pair.
///
/// Conventions (the same as the distance fields', so that an approximant can be built from it):
/// `normal` is the unit vector along Su x Sv; the principal curvatures k1 >= k2 are positive where
/// the surface bends away from `normal` (a sphere parametrised with Su x Sv pointing outward has
/// k1 = k2 = 1/R), i.e. k = -II(w, w) / I(w, w) along the principal direction w; e1, e2 are unit
/// principal directions (tangent) with e1 x e2 = normal. At an umbilic (k1 = k2 to rounding) e1 is
/// Su / |Su|. Curvatures in 1 / world units.
struct SurfaceFrame {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitY();
  double k1 = 0.0;
  double k2 = 0.0;
  /// False where Su x Sv vanishes (|Su x Sv| <= 1e-12 (|Su|^2 + |Sv|^2)): the normal
  /// and curvatures are then undefined; the frame holds `point`, normal = a unit vector
  /// orthogonal to the non-zero first derivative (or +z), and zero curvatures.
  bool regular = true;
};

/// The frame from the position and first and second partial derivatives at a point (any regular
/// parametrisation, not only B-splines). Closed form; no iteration; never throws.
SurfaceFrame surfaceFrame(const SurfaceDerivatives& derivatives);

/// surfaceFrame(surface.derivatives(u, v)). Failure behaviour as BSplineSurface::derivatives().
SurfaceFrame surfaceFrame(const BSplineSurface& surface, double u, double v);

}  // namespace d2vdb
