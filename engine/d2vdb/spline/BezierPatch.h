// The polynomial pieces of a tensor-product B-spline surface in Bézier form.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/spline/BSplineSurface.h"
#include "d2vdb/spline/KnotVector.h"
#include "d2vdb/spline/ParameterInterval.h"

namespace d2vdb {

/// One polynomial piece of a B-spline surface: on its knot cell [intervalU] x [intervalV] the
/// surface equals the tensor-product Bézier patch
///   B(s, t) = sum_a sum_b Bern_{a,p}(s) Bern_{b,q}(t) controlPoints[a (q + 1) + b],
/// s, t in [0, 1] with u = intervalU.at(s), v = intervalV.at(t). The control points' bounding box
/// contains the piece (convex hull property).
struct BezierPatch {
  int degreeU = 0;
  int degreeV = 0;
  int spanU = 0;  ///< knot span index in u (KnotVector::findSpan convention)
  int spanV = 0;  ///< knot span index in v
  ParameterInterval intervalU;
  ParameterInterval intervalV;
  std::vector<Eigen::Vector3d> controlPoints;  ///< (p + 1) (q + 1), index a (q + 1) + b

  /// B(s, t) by Bernstein evaluation (de Casteljau per row, then across). s, t outside [0, 1]
  /// extrapolate.
  Eigen::Vector3d evaluate(double s, double t) const;
};

/// The (p + 1) x (p + 1) matrix M of the knot span `span` (p <= span < n, non-empty) that maps
/// the span's B-spline control points d_0..d_p (the coefficients of N_{span-p..span}) to the
/// Bézier control points of the span's polynomial piece: bezier_c = sum_j M(c, j) d_j (blossoms
/// with p - c arguments at the span's start and c at its end). InputError for an invalid span.
Eigen::MatrixXd bezierExtractionMatrix(const KnotVector& knots, int span);

/// One Bézier patch per non-empty knot cell of the surface's domain, u-major (all v cells of the
/// first u span, then the next u span...). Closed directions give one piece per unique control
/// row/column (their wrapped control points included).
std::vector<BezierPatch> toBezierPatches(const BSplineSurface& surface);

}  // namespace d2vdb
