// SDM I: fitting a B-spline curve to a target whose squared-distance approximants are known (a
// curve target, an offset, a surface level set through the approximant field): Pottmann,
// Leopoldseder and Hofer, "Approximation with active B-spline curves and surfaces" (2002).
#pragma once

#include "d2vdb/field/SquaredDistanceTarget.h"
#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// Deforms `initial` (knots fixed) so that its sensors come close to `target`.
///
/// Each iteration places options.sensorsPerSpan sensors per knot span (fixed parameters), asks the
/// target for the approximant at every sensor (target.approximantsAt, parallel), forms each
/// sensor's quadratic by options.method (fitForm), solves the quadratic model (mean over sensors +
/// smoothing), and controls the step: a line search (step halving) on the true objective mean_k
/// target.squaredDistanceAt(x_k) + smoothing for PDM, SDM and TDM+PDM, a Levenberg-Marquardt
/// damping schedule for TDM. Errors are measured orthogonal to the target. A 2D curve (dimension 2)
/// uses only the xy blocks of the forms and stays in z = 0.
///
/// Automatic smoothness (options.smoothness < 0) is as CurveFitOptions says for closed curves and
/// none for open ones: the one-sided distance (sensors to target) does not hold an open curve's
/// ends, which a bending term would pull in along the target. Stops as CurveFitOptions says; the
/// result states why (FitStatus) and holds the history. Deterministic: bitwise identical for any
/// thread count.
///
/// Throws InputError for invalid options, an initial curve whose control points all coincide, or
/// a sensor of the initial curve outside target.domain() (the message names the sensor and the
/// domain). Later iterates that would leave the domain are treated as failed steps.
CurveFitResult fitCurve(const BSplineCurve& initial, const SquaredDistanceTarget& target,
                        const CurveFitOptions& options = {});

}  // namespace d2vdb
