// Options and result of the B-spline curve fitters (CurveFitter.h, PointCloudFitter.h).
#pragma once

#include <vector>

#include "d2vdb/fit/FitHistory.h"
#include "d2vdb/fit/FitOptions.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// How a curve fit is run (FitOptions): the bending energy is int |x''(u)|^2 du and the
/// stretching energy int |x'(u)|^2 du, with u the curve parameter normalised to [0, 1], and F_k
/// the true squared distance of sensor k (CurveFitter) or of data point k (PointCloudFitter). For
/// a circle of radius R the bending term is 16 pi^4 R^2 smoothness, i.e. it shrinks the fit by
/// about 1560 * smoothness * R (the energy grows with the fourth power of the waviness).
struct CurveFitOptions : FitOptions {
  /// Sensors per knot span (CurveFitter only; PointCloudFitter uses one per data point).
  int sensorsPerSpan = 8;
  /// SDM II on point clouds (with exactSecondOrder): correct every step that uses the exact
  /// second-order terms by the least-squares fit of the control points with the data points'
  /// footpoint parameters on the stepped curve held fixed (it can only lower the objective), and
  /// lengthen a step whose correction gained much more than the quadratic model promised. Along
  /// the curve's reparametrisations (control points sliding along it, which changes the shape
  /// only slightly) the squared distance is a long curved valley that Newton's steps follow in
  /// many short steps; the correction straightens it. false = steps as they are.
  bool footpointCorrection = true;
};

/// The outcome of a curve fit.
struct CurveFitResult : FitReport {
  BSplineCurve curve;                  ///< the final curve (same knots as the initial one)
  std::vector<BSplineCurve> iterates;  ///< with keepIterates: initial curve, then every iterate
};

}  // namespace d2vdb
