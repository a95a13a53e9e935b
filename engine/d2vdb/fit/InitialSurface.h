// Generated initial surfaces for the surface fitters: plane sheets, cylinders and tori, given
// explicitly or placed around a set of points by their principal axes and extents.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// The radius of the control polygon, relative to the circle's radius, of the uniform periodic
/// B-spline of `degree` with `count` control points on a regular polygon that approximates a
/// circle best in the minimax sense (its radius oscillates symmetrically about the circle's), and
/// that approximation's largest radial error relative to the radius. InputError unless
/// 1 <= degree <= 15 and count >= degree + 1.
struct CircleFit {
  double polygonScale = 1.0;
  double relativeError = 0.0;
};
CircleFit periodicCircleFit(int degree, int count);

/// The layout of a tensor-product surface: degrees, control-point counts and closed directions.
/// validate() throws InputError naming the problem: a degree outside 1..15, a count below
/// degree + 1 (an open direction has degree + 1 basis functions at least; a closed direction
/// needs degree + 1 unique control rows).
struct SurfaceLayout {
  int degreeU = 3;
  int degreeV = 3;
  int countU = 8;
  int countV = 8;
  bool closedU = false;
  bool closedV = false;
  void validate() const;
};

/// The flat sheet origin + s edgeU + t edgeV, (s, t) in [0, 1]^2, exactly and with a linear
/// parametrisation (control points at the Greville abscissae of clamped uniform knots on [0, 1]).
/// Both directions open. InputError for an invalid layout, a closed direction, or edges that are
/// parallel or zero.
BSplineSurface planeSheet(const Eigen::Vector3d& origin, const Eigen::Vector3d& edgeU,
                          const Eigen::Vector3d& edgeV, const SurfaceLayout& layout);

/// A circular cylinder of `radius` around the axis from `base` to `base + axis`: the closed
/// direction (exactly one of layout.closedU, closedV) runs around it as the best periodic
/// approximation of the circle (periodicCircleFit), the open direction along the axis (linear
/// parametrisation from base to base + axis). Domains [0, 1]. InputError for an invalid layout,
/// not exactly one closed direction, a zero axis or a non-positive radius.
BSplineSurface cylinderSurface(const Eigen::Vector3d& base, const Eigen::Vector3d& axis,
                               double radius, const SurfaceLayout& layout);

/// A ring torus about the axis through `center` along `axis` (any length): u runs around the axis
/// (major circle, radius `majorRadius`), v around the tube (radius `minorRadius`, v = 0 on the
/// outer equator); the tensor product of the two best periodic circle approximations
/// (control point (i, j) = x_j s_u (cos a_i e1 + sin a_i e2) + z_j axis, with (x_j, z_j) the
/// meridian circle's control polygon). Both directions closed; domains [0, 1]. InputError for an
/// invalid layout, an open direction, a zero axis, or radii not satisfying 0 < minor < major.
BSplineSurface torusSurface(const Eigen::Vector3d& center, const Eigen::Vector3d& axis,
                            double majorRadius, double minorRadius, const SurfaceLayout& layout);

/// Shape of a generated initial surface.
enum class InitialSurfaceShape {
  Plane,     ///< a sheet in the plane of the two leading principal axes over the points' extent
  Cylinder,  ///< around the axis, through the points' mean distance from it
  Torus,     ///< around the axis, with the points' mean major and RMS minor radius
};

/// How initialSurfaceAround() places the surface.
struct InitialSurfaceOptions {
  InitialSurfaceShape shape = InitialSurfaceShape::Plane;
  SurfaceLayout layout;
  /// Multiplies the estimated size: the sheet's extent about its centre, the cylinder's radius,
  /// the torus's minor radius. Must be positive.
  double scale = 1.0;
  /// The cylinder's or torus's axis direction; default: the principal axis whose variance differs
  /// most from the other two (the symmetry axis of a cylinder or torus).
  std::optional<Eigen::Vector3d> axis;
};

/// A surface placed from `points` (a sampling of the target). The centre is the points' mean.
/// Plane: the sheet lies in the plane through the centre orthogonal to the principal axis of
/// least variance, and is the smallest-area rectangle (over in-plane rotations, to 0.01 degree)
/// holding the points' projections, scaled about its centre; u runs along its longer side.
/// Cylinder: axis as above through the centre, radius = mean distance from it, extent along it
/// = the points' range. Torus: axis as above through the centre, major radius = mean distance of
/// the points from the axis within the equatorial plane, minor radius = RMS distance from that
/// circle. InputError for no points, non-finite points, all points on a line (or equal), an
/// invalid layout or shape/layout mismatch (see the functions above), or a non-positive scale.
BSplineSurface initialSurfaceAround(const std::vector<Eigen::Vector3d>& points,
                                    const InitialSurfaceOptions& options);

}  // namespace d2vdb
