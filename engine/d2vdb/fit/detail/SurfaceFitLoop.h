// Internal: the surface fitters' side of the shared fit loop (detail/FitLoop.h): the checks and
// the loop settings of a surface (its thin-plate and membrane matrices) and the surface result.
#pragma once

#include <functional>
#include <vector>

#include "d2vdb/fit/SurfaceFit.h"
#include "d2vdb/fit/detail/FitLoop.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb::detail {

/// Throws InputError when the options are out of range (validateFitOptions(), SplineFit.h) or
/// all control points of `initial` coincide.
void validateSurfaceFit(const BSplineSurface& initial, const SurfaceFitOptions& options);

/// The loop settings for fitting `initial` with `options`: the thin-plate matrix as the bending
/// term (none for degree (1, 1), which has no thin-plate energy of its own but the twist), the
/// membrane term, the step regulariser (thin-plate, or membrane for degree (1, 1)),
/// Levenberg-Marquardt for TDM, tolerances and the progress callback.
FitLoopSettings surfaceLoopSettings(const BSplineSurface& initial,
                                    const SurfaceFitOptions& options);

/// Validates the options and the initial surface, runs the loop and returns the surface result;
/// `interrupt` as FitLoopSettings::interrupt.
SurfaceFitResult runSurfaceFit(
    const BSplineSurface& initial, const SurfaceFitOptions& options, FitProblem& problem,
    std::function<bool(int, const std::vector<Eigen::Vector3d>&)> interrupt = {});

}  // namespace d2vdb::detail
