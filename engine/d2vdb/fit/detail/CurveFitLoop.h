// Internal: the curve fitters' side of the shared fit loop (detail/FitLoop.h): the checks and the
// loop settings of a curve (its smoothing matrices) and the curve result.
#pragma once

#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/fit/detail/FitLoop.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb::detail {

/// Throws InputError when the options are out of range (validateFitOptions(), SplineFit.h) or
/// all control points of `initial` coincide.
void validateCurveFit(const BSplineCurve& initial, const CurveFitOptions& options);

/// The loop settings for fitting `initial` with `options`: the bending Gram matrix G2 (none for
/// degree 1), the stretch term, the step regulariser (Gram matrix of order min(p, 2)),
/// Levenberg-Marquardt for TDM, tolerances and the progress callback.
FitLoopSettings curveLoopSettings(const BSplineCurve& initial, const CurveFitOptions& options);

/// Validates the options and the initial curve, runs the loop and returns the curve result.
CurveFitResult runCurveFit(const BSplineCurve& initial, const CurveFitOptions& options,
                           FitProblem& problem);

}  // namespace d2vdb::detail
