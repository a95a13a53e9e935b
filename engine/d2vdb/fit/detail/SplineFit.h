// Internal: what the curve and surface fitters share around the fit loop (detail/FitLoop.h): the
// option and data-point checks, the loop settings that come straight from FitOptions, the
// degenerate-net check and the result with the fitted spline and its iterates.
#pragma once

#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

#include "d2vdb/fit/FitOptions.h"
#include "d2vdb/fit/detail/FitLoop.h"

namespace d2vdb::detail {

/// Throws InputError when the options are out of range (fewer than one sensor per span, negative
/// weights or tolerances, a negative iteration cap, ...).
void validateFitOptions(const FitOptions& options, int sensorsPerSpan);

/// Throws InputError when all `controlPoints` coincide (to 1e-12 of their magnitude); `what` names
/// the spline ("the initial curve").
void requireNonDegenerate(const std::vector<Eigen::Vector3d>& controlPoints,
                          const std::string& what);

/// Throws InputError when the point cloud `points` is empty (nothing to fit `what` to: "a curve")
/// or a point has a non-finite coordinate or, with `planar`, z != 0 (the first such point named).
void requireDataPoints(const std::vector<Eigen::Vector3d>& points, const std::string& what,
                       bool planar = false);

/// The loop settings taken over from `options` as they are (bending weight, Levenberg-Marquardt
/// for TDM, damping, automatic bias, iteration cap, tolerances, iterates, progress); the caller
/// adds the spline's dimension, name and smoothing matrices.
FitLoopSettings loopSettingsFrom(const FitOptions& options);

/// Runs the loop from `initial`'s control points and returns Result {report, fitted spline,
/// iterates} (CurveFitResult, SurfaceFitResult): the splines keep `initial`'s knots.
template <class Result, class Spline>
Result runSplineFit(const Spline& initial, const FitLoopSettings& settings, FitProblem& problem) {
  FitLoopResult loop = runFitLoop(initial.controlPoints(), settings, problem);
  Spline fitted = initial;
  fitted.setControlPoints(std::move(loop.controlPoints));
  std::vector<Spline> iterates;
  iterates.reserve(loop.iterates.size());
  for (std::vector<Eigen::Vector3d>& points : loop.iterates) {
    iterates.push_back(initial);
    iterates.back().setControlPoints(std::move(points));
  }
  return Result{{loop.status, std::move(loop.reason), std::move(loop.history)},
                std::move(fitted),
                std::move(iterates)};
}

}  // namespace d2vdb::detail
