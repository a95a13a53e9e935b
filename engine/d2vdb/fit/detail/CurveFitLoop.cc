// The curve fitters' side of the shared fit loop (detail/CurveFitLoop.h).
#include "d2vdb/fit/detail/CurveFitLoop.h"

#include <algorithm>

#include "d2vdb/fit/detail/SmoothingMatrix.h"
#include "d2vdb/fit/detail/SplineFit.h"

namespace d2vdb::detail {

void validateCurveFit(const BSplineCurve& initial, const CurveFitOptions& options) {
  validateFitOptions(options, options.sensorsPerSpan);
  requireNonDegenerate(initial.controlPoints(), "the initial curve");
}

FitLoopSettings curveLoopSettings(const BSplineCurve& initial, const CurveFitOptions& options) {
  const int p = initial.degree();
  FitLoopSettings settings = loopSettingsFrom(options);
  settings.dimension = initial.dimension();
  settings.splineName = "curve";
  if (p >= 2) settings.bending = derivativeGramMatrix(initial, 2);
  if (options.stretch > 0.0)
    settings.fixedSmoothing = options.stretch * derivativeGramMatrix(initial, 1);
  if (options.stepSmoothness > 0.0) {
    settings.stepRegularizer = derivativeGramMatrix(initial, std::min(p, 2));
    settings.stepSmoothness = options.stepSmoothness;
  }
  return settings;
}

CurveFitResult runCurveFit(const BSplineCurve& initial, const CurveFitOptions& options,
                           FitProblem& problem) {
  validateCurveFit(initial, options);
  return runSplineFit<CurveFitResult>(initial, curveLoopSettings(initial, options), problem);
}

}  // namespace d2vdb::detail
