// What the curve and surface fitters share around the fit loop (detail/SplineFit.h).
#include "d2vdb/fit/detail/SplineFit.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {

void validateFitOptions(const FitOptions& options, int sensorsPerSpan) {
  const auto require = [](bool ok, const std::string& message) {
    if (!ok) throw InputError(message);
  };
  require(sensorsPerSpan >= 1, "sensors per knot span must be at least 1");
  require(options.maxIterations >= 0, "the iteration cap must not be negative");
  require(std::isfinite(options.smoothness),
          "the smoothness weight must be finite (negative = automatic)");
  require(std::isfinite(options.automaticSmoothingBias) && options.automaticSmoothingBias > 0.0,
          "the automatic smoothing bias must be finite and positive");
  require(std::isfinite(options.stretch) && options.stretch >= 0.0,
          "the stretch weight must be finite and non-negative");
  require(std::isfinite(options.pdmWeight) && options.pdmWeight >= 0.0,
          "the PDM weight of tdm+pdm must be finite and non-negative");
  require(std::isfinite(options.distanceTolerance) && options.distanceTolerance >= 0.0,
          "the distance tolerance must be finite and non-negative");
  require(std::isfinite(options.stepTolerance) && options.stepTolerance >= 0.0,
          "the step tolerance must be finite and non-negative");
  require(std::isfinite(options.moveTolerance) && options.moveTolerance >= 0.0,
          "the move tolerance must be finite and non-negative");
  require(std::isfinite(options.objectiveTolerance) && options.objectiveTolerance >= 0.0,
          "the objective tolerance must be finite and non-negative");
  require(std::isfinite(options.stepSmoothness) && options.stepSmoothness >= 0.0,
          "the step smoothness must be finite and non-negative");
  require(std::isfinite(options.initialDamping) && options.initialDamping >= 0.0,
          "the initial damping must be finite and non-negative");
}

void requireDataPoints(const std::vector<Eigen::Vector3d>& points, const std::string& what,
                       bool planar) {
  if (points.empty()) {
    throw InputError("the point cloud is empty: there is nothing to fit " + what + " to");
  }
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!points[k].allFinite()) {
      throw InputError("data point " + std::to_string(k) + " has a non-finite coordinate");
    }
    if (planar && points[k].z() != 0.0) {
      throw InputError("data point " + std::to_string(k) +
                       " has z != 0 but the curve is 2D; fit a 3D curve or project the data");
    }
  }
}

void requireNonDegenerate(const std::vector<Eigen::Vector3d>& controlPoints,
                          const std::string& what) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : controlPoints) box.extend(point);
  const double magnitude =
      std::max(box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff());
  if (box.sizes().maxCoeff() <= 1e-12 * std::max(magnitude, 1e-300)) {
    throw InputError(what +
                     " is degenerate: all its control points coincide; give one with distinct "
                     "control points (or let d2vdb generate one)");
  }
}

FitLoopSettings loopSettingsFrom(const FitOptions& options) {
  FitLoopSettings settings;
  settings.bendingWeight = options.smoothness;
  settings.levenbergMarquardt = options.method == FitMethod::TDM;
  settings.initialDamping = options.initialDamping;
  settings.automaticBias = options.automaticSmoothingBias;
  settings.maxIterations = options.maxIterations;
  settings.distanceTolerance = options.distanceTolerance;
  settings.stepTolerance = options.stepTolerance;
  settings.moveTolerance = options.moveTolerance;
  settings.objectiveTolerance = options.objectiveTolerance;
  settings.keepIterates = options.keepIterates;
  settings.progress = options.progress;
  return settings;
}

}  // namespace d2vdb::detail
