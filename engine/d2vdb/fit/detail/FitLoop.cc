// The iteration shared by the curve fitters (CurveFitter, PointCloudFitter) and the surface
// fitters (SurfaceFitter) (detail/FitLoop.h).
#include "d2vdb/fit/detail/FitLoop.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>

#include "d2vdb/core/Error.h"
#include "d2vdb/fit/QuadraticModel.h"
#include "d2vdb/fit/SensorBasis.h"
#include "d2vdb/fit/SmoothingMatrix.h"
#include "d2vdb/fit/SurfaceSensorBasis.h"
#include "d2vdb/fit/ThinPlateMatrix.h"

namespace d2vdb {

const char* fitStatusName(FitStatus status) {
  switch (status) {
    case FitStatus::Converged:
      return "converged";
    case FitStatus::Stalled:
      return "stalled";
    case FitStatus::IterationCap:
      return "iteration cap";
  }
  return "unknown";
}

namespace detail {
namespace {

bool usesDamping(FitMethod method) {
  return method == FitMethod::TDM;
}

double objectiveOf(const DataError& error, double smoothingEnergy) {
  if (!error.valid || error.count == 0) return std::numeric_limits<double>::infinity();
  return error.sum / error.count + smoothingEnergy;
}

std::vector<Eigen::Vector3d> moved(const std::vector<Eigen::Vector3d>& points,
                                   const std::vector<Eigen::Vector3d>& displacement, double scale) {
  std::vector<Eigen::Vector3d> result(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) result[i] = points[i] + scale * displacement[i];
  return result;
}

double largestMove(const std::vector<Eigen::Vector3d>& displacement) {
  double largest = 0.0;
  for (const Eigen::Vector3d& c : displacement) largest = std::max(largest, c.norm());
  return largest;
}

}  // namespace

namespace {

template <typename Options>
void validateOptions(const Options& options) {
  const auto require = [](bool ok, const std::string& message) {
    if (!ok) throw InputError(message);
  };
  require(options.sensorsPerSpan >= 1, "sensors per knot span must be at least 1");
  require(options.maxIterations >= 0, "the iteration cap must not be negative");
  require(std::isfinite(options.smoothness),
          "the smoothness weight must be finite (negative = automatic)");
  require(std::isfinite(options.stretch) && options.stretch >= 0.0,
          "the stretch weight must be finite and non-negative");
  require(std::isfinite(options.pdmWeight) && options.pdmWeight >= 0.0,
          "the PDM weight of tdm+pdm must be finite and non-negative");
  require(std::isfinite(options.distanceTolerance) && options.distanceTolerance >= 0.0,
          "the distance tolerance must be finite and non-negative");
  require(std::isfinite(options.stepTolerance) && options.stepTolerance >= 0.0,
          "the step tolerance must be finite and non-negative");
  require(std::isfinite(options.objectiveTolerance) && options.objectiveTolerance >= 0.0,
          "the objective tolerance must be finite and non-negative");
  require(std::isfinite(options.stepSmoothness) && options.stepSmoothness >= 0.0,
          "the step smoothness must be finite and non-negative");
  require(std::isfinite(options.initialDamping) && options.initialDamping >= 0.0,
          "the initial damping must be finite and non-negative");
}

}  // namespace

void validateFitOptions(const CurveFitOptions& options) {
  validateOptions(options);
}

void validateFitOptions(const SurfaceFitOptions& options) {
  validateOptions(options);
}

namespace {

template <typename Spline>
void requireDistinctControlPoints(const Spline& curve, const char* what) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : curve.controlPoints()) box.extend(point);
  const double magnitude =
      std::max(box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff());
  if (box.sizes().maxCoeff() <= 1e-12 * std::max(magnitude, 1e-300)) {
    throw InputError(std::string(what) +
                     " is degenerate: all its control points coincide; give one with distinct "
                     "control points (or let d2vdb generate one)");
  }
}

}  // namespace

void requireNonDegenerate(const BSplineCurve& curve, const char* what) {
  requireDistinctControlPoints(curve, what);
}

void requireNonDegenerate(const BSplineSurface& surface, const char* what) {
  requireDistinctControlPoints(surface, what);
}

namespace {

/// Fraction of the target's resolution (a field's voxel) below which a step that does not lower
/// the objective counts as convergence: the approximants' own error (footpoints to a few hundredths
/// of a voxel, piecewise per voxel) makes the objective rough on that scale.
constexpr double kResolvedFraction = 0.01;
/// Smallest relative objective decrease that keeps the first automatic phase going.
constexpr double kCoarseObjectiveTolerance = 1e-5;
/// Smallest relative objective decrease that keeps the automatic refinement phase going.
constexpr double kRefineObjectiveTolerance = 1e-6;
/// Smallest relative objective decrease that keeps a surface's first automatic phase going.
constexpr double kSurfaceCoarseObjectiveTolerance = 1e-4;
/// The relative step-regulariser weight of a surface's unsmoothed automatic phase.
constexpr double kSurfaceRefineStepSmoothness = 1e-3;

/// `progress` for one of two equal halves of the work, the one starting at `start` (0 or 0.5);
/// empty when `progress` is.
ProgressCallback progressPart(const ProgressCallback& progress, double start) {
  if (!progress) return {};
  return [&progress, start](std::string_view stage, double fraction) {
    progress(stage, start + 0.5 * fraction);
  };
}

// What the loop needs to know about the spline type: its smoothing and step-regulariser
// matrices, dimension, name, sensor basis and where the result keeps it.

Eigen::SparseMatrix<double> smoothingMatrix(const BSplineCurve& initial, double smoothness,
                                            const CurveFitOptions& options) {
  const int n = initial.controlPointCount();
  const int p = initial.degree();
  Eigen::SparseMatrix<double> smoothing(n, n);
  if (smoothness > 0.0 && p >= 2) smoothing += smoothness * derivativeGramMatrix(initial, 2);
  if (options.stretch > 0.0) smoothing += options.stretch * derivativeGramMatrix(initial, 1);
  return smoothing;
}

Eigen::SparseMatrix<double> smoothingMatrix(const BSplineSurface& initial, double smoothness,
                                            const SurfaceFitOptions& options) {
  const int n = initial.countU() * initial.countV();
  Eigen::SparseMatrix<double> smoothing(n, n);
  if (smoothness > 0.0) smoothing += smoothness * thinPlateMatrix(initial);
  if (options.stretch > 0.0) smoothing += options.stretch * membraneMatrix(initial);
  return smoothing;
}

Eigen::SparseMatrix<double> regularizerMatrix(const BSplineCurve& initial) {
  return derivativeGramMatrix(initial, std::min(initial.degree(), 2));
}

Eigen::SparseMatrix<double> regularizerMatrix(const BSplineSurface& initial) {
  // Degree (1, 1) has no thin-plate energy of its own (only the twist): use the membrane's.
  if (initial.degreeU() < 2 && initial.degreeV() < 2) return membraneMatrix(initial);
  return thinPlateMatrix(initial);
}

int dimensionOf(const BSplineCurve& curve) {
  return curve.dimension();
}
int dimensionOf(const BSplineSurface&) {
  return 3;
}

int controlPointCountOf(const BSplineCurve& curve) {
  return curve.controlPointCount();
}
int controlPointCountOf(const BSplineSurface& surface) {
  return surface.countU() * surface.countV();
}

const char* splineName(const BSplineCurve&) {
  return "curve";
}
const char* splineName(const BSplineSurface&) {
  return "surface";
}

std::unique_ptr<SensorMap> makeBasis(const BSplineCurve& curve,
                                     const std::vector<double>& parameters) {
  return std::make_unique<SensorBasis>(curve, parameters);
}
std::unique_ptr<SensorMap> makeBasis(const BSplineSurface& surface,
                                     const std::vector<Eigen::Vector2d>& parameters) {
  return std::make_unique<SurfaceSensorBasis>(surface, parameters);
}

BSplineCurve& splineOf(CurveFitResult& result) {
  return result.curve;
}
BSplineSurface& splineOf(SurfaceFitResult& result) {
  return result.surface;
}

/// One fit with a fixed bending (curves) or thin-plate (surfaces) weight `smoothness`
/// (options.smoothness is ignored).
template <typename Spline>
typename FitTypes<Spline>::Result runFitPhase(const Spline& initial,
                                              const typename FitTypes<Spline>::Options& options,
                                              double smoothness, FitProblemFor<Spline>& problem) {
  using Result = typename FitTypes<Spline>::Result;
  using Parameter = typename FitTypes<Spline>::Parameter;
  const int n = controlPointCountOf(initial);
  QuadraticModel model(n, dimensionOf(initial), smoothingMatrix(initial, smoothness, options));
  if (options.stepSmoothness > 0.0) {
    model.setStepRegularizer(regularizerMatrix(initial), options.stepSmoothness);
  }

  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : initial.controlPoints()) box.extend(point);
  const double size = box.sizes().maxCoeff();

  Result result{initial, FitStatus::IterationCap, "", {}, {}};
  Spline& current = splineOf(result);
  std::vector<Eigen::Vector3d> points = initial.controlPoints();
  const DataError initialError = problem.measure(initial);
  if (!initialError.valid) {
    throw InputError(std::string("the initial ") + splineName(initial) +
                     " is not inside the region where the target answers");
  }
  problem.accept();
  double objective = objectiveOf(initialError, model.smoothingEnergy(points));
  result.history.push_back({0, objective, std::sqrt(initialError.sum / initialError.count),
                            std::sqrt(initialError.maxSquared), 0.0, 0.0, 0.0});
  if (options.keepIterates) result.iterates.push_back(initial);

  double damping = usesDamping(options.method) ? options.initialDamping : 0.0;
  std::vector<Parameter> parameters;
  std::vector<QuadraticForm> forms;
  bool stopped = false;
  for (int iteration = 1; iteration <= options.maxIterations && !stopped; ++iteration) {
    if (options.progress) {
      options.progress("fit", static_cast<double>(iteration - 1) / options.maxIterations);
    }
    problem.linearize(current, options, parameters, forms);
    std::unique_ptr<SensorMap> ownBasis;
    const SensorMap* basis = problem.fixedBasis();
    if (basis == nullptr) basis = (ownBasis = makeBasis(current, parameters)).get();

    // Step control: TDM raises the damping until a full step lowers E; the other methods halve
    // the step (a line search on the true squared distances).
    bool accepted = false;
    bool flat = false;  // the objective at the full step equals E to rounding
    double firstStep = 0.0;
    double scale = 1.0;
    double usedDamping = damping;
    DataError acceptedError;
    double acceptedObjective = objective;
    std::vector<Eigen::Vector3d> acceptedPoints;
    const int dampingAttempts = usesDamping(options.method) ? 12 : 1;
    for (int attempt = 0; attempt < dampingAttempts && !accepted; ++attempt) {
      const std::vector<Eigen::Vector3d> step = model.solve(*basis, forms, points, damping);
      if (attempt == 0) firstStep = largestMove(step);
      const int halvings = usesDamping(options.method) ? 1 : 30;
      scale = 1.0;
      for (int h = 0; h < halvings; ++h, scale *= 0.5) {
        std::vector<Eigen::Vector3d> candidatePoints = moved(points, step, scale);
        Spline candidate = current;
        candidate.setControlPoints(candidatePoints);
        const DataError error = problem.measure(candidate);
        const double value = objectiveOf(error, model.smoothingEnergy(candidatePoints));
        if (attempt == 0 && h == 0 && std::abs(value - objective) <= 1e-12 * objective) {
          flat = true;
        }
        if (value < objective) {
          accepted = true;
          acceptedError = error;
          acceptedObjective = value;
          acceptedPoints = std::move(candidatePoints);
          usedDamping = damping;
          break;
        }
        if (largestMove(step) * scale < 1e-3 * options.stepTolerance * size) break;
      }
      if (!accepted && usesDamping(options.method)) damping = std::max(10.0 * damping, 1e-6);
    }
    if (!accepted) {
      if (firstStep <= options.stepTolerance * size || flat) {
        result.status = FitStatus::Converged;
        result.reason = "the objective no longer changes beyond rounding";
      } else if (firstStep <= kResolvedFraction * problem.resolution()) {
        result.status = FitStatus::Converged;
        std::ostringstream reason;
        reason << "the model's step (" << firstStep << ") is below " << kResolvedFraction
               << " of the target's resolution (" << problem.resolution()
               << "): the target resolves no further improvement";
        result.reason = reason.str();
      } else {
        result.status = FitStatus::Stalled;
        result.reason = "no step along the solution of the quadratic model lowered the objective";
      }
      stopped = true;
      break;
    }
    problem.accept();
    double stepLength = 0.0;
    for (int i = 0; i < n; ++i) {
      stepLength = std::max(stepLength, (acceptedPoints[static_cast<std::size_t>(i)] -
                                         points[static_cast<std::size_t>(i)])
                                            .norm());
    }
    const double relativeDecrease = (objective - acceptedObjective) / objective;
    points = std::move(acceptedPoints);
    current.setControlPoints(points);
    objective = acceptedObjective;
    const double rms = std::sqrt(acceptedError.sum / acceptedError.count);
    result.history.push_back({iteration, objective, rms, std::sqrt(acceptedError.maxSquared),
                              stepLength, scale, usedDamping});
    if (options.keepIterates) result.iterates.push_back(current);
    if (usesDamping(options.method) && scale == 1.0) damping = std::max(damping / 3.0, 1e-9);

    if (stepLength <= options.stepTolerance * size) {
      result.status = FitStatus::Converged;
      result.reason = "the largest control-point move fell below the step tolerance";
      stopped = true;
    } else if (options.distanceTolerance > 0.0 && rms <= options.distanceTolerance) {
      result.status = FitStatus::Converged;
      result.reason = "the RMS distance reached the distance tolerance";
      stopped = true;
    } else if (relativeDecrease < options.objectiveTolerance) {
      result.status = FitStatus::Converged;
      result.reason = "the objective decreased by less than the objective tolerance";
      stopped = true;
    }
  }
  if (!stopped) {
    result.status = FitStatus::IterationCap;
    std::ostringstream reason;
    reason << "reached the iteration cap of " << options.maxIterations << " while still improving";
    result.reason = reason.str();
  }
  if (options.progress) options.progress("fit", 1.0);
  return result;
}

}  // namespace

CurveFitResult runFitLoop(const BSplineCurve& initial, const CurveFitOptions& options,
                          FitProblem& problem) {
  validateFitOptions(options);
  requireNonDegenerate(initial, "the initial curve");
  if (options.smoothness >= 0.0 || !initial.isClosed()) {
    return runFitPhase(initial, options, std::max(0.0, options.smoothness), problem);
  }
  // Automatic bending weight of a closed curve: converge (or stall) with kAutoClosedSmoothness,
  // which fixes the parametrisation and makes SDM converge fast, then refine with a thousandth of
  // it, which removes most of its bias (it grows with the curve's waviness) at the cost of a slower
  // tail.
  CurveFitOptions coarseOptions = options;
  // The first phase only has to get near its (biased) optimum: the refinement moves on from it.
  coarseOptions.objectiveTolerance =
      std::max(options.objectiveTolerance, kCoarseObjectiveTolerance);
  coarseOptions.progress = progressPart(options.progress, 0.0);
  CurveFitResult result = runFitPhase(initial, coarseOptions, kAutoClosedSmoothness, problem);
  const int remaining = options.maxIterations - result.iterations();
  const bool reachedTolerance = options.distanceTolerance > 0.0 &&
                                result.history.back().rmsDistance <= options.distanceTolerance;
  if (result.status == FitStatus::IterationCap || reachedTolerance || remaining <= 0) {
    if (options.progress) options.progress("fit", 1.0);
    return result;
  }
  CurveFitOptions refineOptions = options;
  refineOptions.maxIterations = remaining;
  // What is left to gain is mostly the curve sliding along itself, which a weak bending term
  // pulls on only slowly: stop once the objective barely moves.
  refineOptions.objectiveTolerance =
      std::max(options.objectiveTolerance, kRefineObjectiveTolerance);
  refineOptions.progress = progressPart(options.progress, 0.5);
  CurveFitResult refined =
      runFitPhase(result.curve, refineOptions, kAutoRefinedSmoothness, problem);
  const int offset = result.iterations();
  for (std::size_t row = 1; row < refined.history.size(); ++row) {
    FitIteration iteration = refined.history[row];
    iteration.iteration += offset;
    result.history.push_back(iteration);
  }
  for (std::size_t i = 1; i < refined.iterates.size(); ++i) {
    result.iterates.push_back(std::move(refined.iterates[i]));
  }
  result.curve = std::move(refined.curve);
  result.status = refined.status;
  result.reason = refined.reason;
  return result;
}

SurfaceFitResult runFitLoop(const BSplineSurface& initial, const SurfaceFitOptions& options,
                            SurfaceFitProblem& problem) {
  validateFitOptions(options);
  requireNonDegenerate(initial, "the initial surface");
  if (options.smoothness >= 0.0) {
    return runFitPhase(initial, options, options.smoothness, problem);
  }
  // Automatic: converge roughly with the thin-plate weight kAutoSurfaceSmoothness, which fixes the
  // parametrisation (the tangential freedom of the sensors), then continue without smoothing, the
  // steps damped by the thin-plate energy of the displacement only: that damping vanishes at a
  // fixed point, so the result is not biased by the smoothing.
  SurfaceFitOptions coarseOptions = options;
  coarseOptions.objectiveTolerance =
      std::max(options.objectiveTolerance, kSurfaceCoarseObjectiveTolerance);
  coarseOptions.progress = progressPart(options.progress, 0.0);
  SurfaceFitResult result = runFitPhase(initial, coarseOptions, kAutoSurfaceSmoothness, problem);
  const int remaining = options.maxIterations - result.iterations();
  const bool reachedTolerance = options.distanceTolerance > 0.0 &&
                                result.history.back().rmsDistance <= options.distanceTolerance;
  if (result.status == FitStatus::IterationCap || reachedTolerance || remaining <= 0) {
    if (options.progress) options.progress("fit", 1.0);
    return result;
  }
  SurfaceFitOptions refineOptions = options;
  refineOptions.maxIterations = remaining;
  if (!(refineOptions.stepSmoothness > 0.0)) {
    refineOptions.stepSmoothness = kSurfaceRefineStepSmoothness;
  }
  refineOptions.progress = progressPart(options.progress, 0.5);
  SurfaceFitResult refined = runFitPhase(result.surface, refineOptions, 0.0, problem);
  const int offset = result.iterations();
  for (std::size_t row = 1; row < refined.history.size(); ++row) {
    FitIteration iteration = refined.history[row];
    iteration.iteration += offset;
    result.history.push_back(iteration);
  }
  for (std::size_t i = 1; i < refined.iterates.size(); ++i) {
    result.iterates.push_back(std::move(refined.iterates[i]));
  }
  result.surface = std::move(refined.surface);
  result.status = refined.status;
  result.reason = refined.reason;
  return result;
}

}  // namespace detail
}  // namespace d2vdb
