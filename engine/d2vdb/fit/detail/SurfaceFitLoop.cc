// The surface fitters' side of the shared fit loop (detail/SurfaceFitLoop.h).
#include "d2vdb/fit/detail/SurfaceFitLoop.h"

#include <utility>

#include "d2vdb/fit/detail/SplineFit.h"
#include "d2vdb/fit/detail/ThinPlateMatrix.h"

namespace d2vdb::detail {

void validateSurfaceFit(const BSplineSurface& initial, const SurfaceFitOptions& options) {
  validateFitOptions(options, options.sensorsPerSpan);
  requireNonDegenerate(initial.controlPoints(), "the initial surface");
}

FitLoopSettings surfaceLoopSettings(const BSplineSurface& initial,
                                    const SurfaceFitOptions& options) {
  const bool bilinear = initial.degreeU() < 2 && initial.degreeV() < 2;
  FitLoopSettings settings = loopSettingsFrom(options);
  settings.dimension = 3;
  settings.splineName = "surface";
  if (!bilinear) settings.bending = thinPlateMatrix(initial);
  if (options.stretch > 0.0) settings.fixedSmoothing = options.stretch * membraneMatrix(initial);
  if (options.stepSmoothness > 0.0) {
    settings.stepRegularizer = bilinear ? membraneMatrix(initial) : thinPlateMatrix(initial);
    settings.stepSmoothness = options.stepSmoothness;
  }
  return settings;
}

SurfaceFitResult runSurfaceFit(
    const BSplineSurface& initial, const SurfaceFitOptions& options, FitProblem& problem,
    std::function<bool(int, const std::vector<Eigen::Vector3d>&)> interrupt) {
  validateSurfaceFit(initial, options);
  FitLoopSettings settings = surfaceLoopSettings(initial, options);
  settings.interrupt = std::move(interrupt);
  return runSplineFit<SurfaceFitResult>(initial, settings, problem);
}

}  // namespace d2vdb::detail
