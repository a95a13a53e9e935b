// SDM II (Wang, Pottmann, Liu 2006): fitting a B-spline curve to a point cloud with errors
// measured orthogonal to the active curve.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// The approximant of the squared distance from `dataPoint` to the active curve, attached to the
/// curve at the data point's footpoint C(t) (SDM II of Wang, Pottmann and Liu 2006): kind Curve,
/// footpoint C(t), tangent and curvature vector of the curve at t, normal toward the data point (in
/// 2D the in-plane normal when the point lies on the curve), distance |dataPoint - C(t)|; the ends
/// of an open curve get kFlagEndPoint. Its form(term), read with the roles of footpoint and data
/// point exchanged, is the error term of Wang, Pottmann and Liu: for SDM d/(d + rho) ((C - X).T)^2
/// + ((C - X).N)^2 on the convex side and ((C - X).N)^2 on the concave side. Throws InputError for
/// t outside an open curve's domain.
Approximant curveApproximantAt(const BSplineCurve& curve, double t,
                               const Eigen::Vector3d& dataPoint);

/// Fits `initial` (knots fixed) to the point cloud `points` by SDM II: every iteration projects
/// each data point onto the current curve (CurveProjector::nearest, started from the previous
/// footpoint's segment, in parallel), forms its error term from curveApproximantAt() under
/// options.method (PDM: the classic point-distance fit with parameter correction; TDM; SDM;
/// TDM+PDM), and solves the quadratic model for the curve points C(t) near the data. For SDM
/// (with options.exactSecondOrder) each data point also contributes the exact second-order terms
/// of its squared distance to the moving curve: with r = C(t) - X and the footpoint parameter t
/// following the control points, the Hessian over the footpoint's control points is
/// I (x) B B^T - u u^T / D, u = B (x) C' + B' (x) r, D = |C'|^2 + r . C'' (B the basis values,
/// B' their derivatives at t); the SDM term is its translation part with the curvature weight
/// clamped. The loop blends the rest in by a trust-region rule (FitOptions::exactSecondOrder), so
/// that the curve's sliding along itself, which the SDM term over-damps, converges like Newton's
/// method. The line search (or TDM's damping) uses the true objective mean_k min_t |C(t) - X_k|^2 +
/// smoothing. The two ends of an open curve are also pulled (PDM) toward their nearest data
/// points, one term each, so that the curve does not run on past the data where nothing would
/// hold it. A 2D curve keeps z = 0 and uses the xy coordinates of the data (z must then be 0).
/// Deterministic for any thread count.
///
/// Throws InputError for an empty cloud, non-finite coordinates, 2D data with z != 0, more
/// control points than data points (which cannot determine them), invalid options, or an initial
/// curve whose control points all coincide.
CurveFitResult fitCurveToPoints(const BSplineCurve& initial,
                                const std::vector<Eigen::Vector3d>& points,
                                const CurveFitOptions& options = {});

}  // namespace d2vdb
