// Internal: the curve fitters' side of the shared fit loop (detail/FitLoop.h): option checks,
// the loop settings of a curve (its smoothing matrices) and the curve result.
#pragma once

#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/fit/detail/FitLoop.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb::detail {

/// Throws InputError when the options are out of range (negative weights, no iterations, ...).
void validateFitOptions(const CurveFitOptions& options);

/// Throws InputError when all control points of `curve` coincide (to 1e-12 of their magnitude).
void requireNonDegenerate(const BSplineCurve& curve, const char* what);

/// The loop settings for fitting `initial` with `options`: the bending Gram matrix G2 (none for
/// degree 1), the stretch term, the step regulariser (Gram matrix of order min(p, 2)),
/// Levenberg-Marquardt for TDM, tolerances and the progress callback.
FitLoopSettings curveLoopSettings(const BSplineCurve& initial, const CurveFitOptions& options);

/// Validates the options and the initial curve, runs the loop and returns the curve result.
CurveFitResult runCurveFit(const BSplineCurve& initial, const CurveFitOptions& options,
                           FitProblem& problem);

}  // namespace d2vdb::detail
