// Generated initial curves for the fitters: an ellipse or circle around a set of points, or a
// least-squares B-spline through an ordered polyline.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// Shape of a generated closed initial curve.
enum class InitialShape {
  Ellipse,  ///< principal axes of the points, semi-axes = `scale` x their extent along each axis
  Circle,   ///< in the principal plane, radius = `scale` x the largest extent
};

/// A closed B-spline (uniform periodic knots, `controlPoints` unique points) approximating an
/// ellipse or circle around `points`: centre = their mean; plane and axes = the two leading
/// principal directions (xy for dimension 2); semi-axes = scale times the largest |(q - centre) .
/// axis| (a flat direction gets at least 1/10 of the other). The B-spline is the least-squares
/// fit to 16 samples per control point of that ellipse, so it lies within a small fraction of its
/// size of it. Throws InputError for no points, non-finite points, all points equal, dimension
/// not 2 or 3, degree outside 1..15, controlPoints < degree + 1, or scale <= 0.
BSplineCurve initialCurveAround(const std::vector<Eigen::Vector3d>& points, InitialShape shape,
                                int degree, int controlPoints, int dimension, double scale = 1.2);

/// The least-squares B-spline of `degree` with `controlPoints` control points through the ordered
/// `points` (chord-length parameters; open curves use a clamped uniform knot vector and pass
/// near both ends, closed curves a uniform periodic one and treat the points as a loop), with a
/// small bending term (1e-9) that keeps spans without points well defined. Same InputError
/// conditions as initialCurveAround(), plus fewer than 2 distinct points.
BSplineCurve fitPolylineLeastSquares(const std::vector<Eigen::Vector3d>& points, bool closed,
                                     int degree, int controlPoints, int dimension);

}  // namespace d2vdb
