// Options, per-iteration history and result of the B-spline curve fitters (CurveFitter.h,
// PointCloudFitter.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/fit/FitMethod.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// The bending weight a closed curve first converges with when CurveFitOptions::smoothness is
/// automatic (see there).
inline constexpr double kAutoClosedSmoothness = 1e-8;
/// The bending weight of the refinement that follows, when smoothness is automatic.
inline constexpr double kAutoRefinedSmoothness = 1e-11;

/// How a fit is run. Distances are world units; the objective is
///   E(P) = mean_k F_k(x_k(P)) + smoothness * int |x''(u)|^2 du + stretch * int |x'(u)|^2 du
/// with u the curve parameter normalised to [0, 1] (SmoothingMatrix.h) and F_k the true squared
/// distance of sensor k (CurveFitter) or of data point k (PointCloudFitter). Both smoothing
/// weights are dimensionless; for a circle of radius R the bending term is 16 pi^4 R^2
/// smoothness, i.e. it shrinks the fit by about 1560 * smoothness * R.
struct CurveFitOptions {
  FitMethod method = FitMethod::SDM;
  /// Sensors per knot span (CurveFitter only; PointCloudFitter uses one per data point).
  int sensorsPerSpan = 8;
  /// Weight of the PDM term in FitMethod::TDMPlusPDM.
  double pdmWeight = 0.01;
  /// lambda2: weight of the bending energy int |x''|^2 of the curve. It regularises the
  /// tangential freedom of the sensors (a unique parametrisation, fast SDM convergence) but
  /// biases the fit: it shrinks a circle-like closed curve by about 1560 * smoothness * R
  /// (1.6e-5 R at 1e-8), a wavy one far more (the energy grows with the fourth power of the
  /// waviness: at 1e-8 a seven-lobed flower of size 2 ends 0.015 off), and shortens open curves,
  /// whose ends the one-sided distance barely holds. Negative (the default) = automatic: open
  /// curves get 0; closed curves converge with kAutoClosedSmoothness (to a relative objective
  /// decrease of at least 1e-5) and then continue from that result with kAutoRefinedSmoothness
  /// (to at least 1e-6; the flower then ends 9e-5 off), the history running on through both
  /// phases (its objective uses each phase's weight).
  double smoothness = -1.0;
  /// lambda1: weight of the stretching energy int |x'|^2.
  double stretch = 0.0;
  /// Step regularisation: rho of QuadraticModel::setStepRegularizer with the bending Gram matrix
  /// of the displacement, relative to the mean diagonal of the data term. Damps rough and
  /// tangential (reparametrising) moves without biasing the fitted curve, at the price of slower
  /// convergence; 0 (default) = off.
  double stepSmoothness = 0.0;
  /// Iteration cap.
  int maxIterations = 100;
  /// Converged when the RMS distance falls to this (world units; 0 = not used).
  double distanceTolerance = 0.0;
  /// Converged when the largest control-point move of an iteration is below this fraction of the
  /// initial curve's size (largest side of its control points' bounding box).
  double stepTolerance = 1e-9;
  /// Converged when an accepted step lowers the objective by less than this fraction of it (the
  /// objective no longer changes; for SDM II the curve then only slides along itself).
  double objectiveTolerance = 1e-8;
  /// Initial Levenberg-Marquardt damping for TDM, relative to the mean diagonal of the system;
  /// divided by 3 after a full step, multiplied by 10 when a step fails to decrease E.
  double initialDamping = 1e-3;
  /// Keep every iterate in CurveFitResult::iterates (for drawing).
  bool keepIterates = false;
  /// Progress: stage "fit", fraction = iteration / maxIterations.
  ProgressCallback progress;
};

/// Why a fit stopped.
enum class FitStatus {
  Converged,     ///< the step, the RMS distance or the relative decrease of the objective fell
                 ///< below its tolerance, or no step lowered the objective although the model's
                 ///< step was below 1/100 of the target's resolution (a field's voxel size)
  Stalled,       ///< no step along the model's solution lowered the objective (line search /
                 ///< damping exhausted) although the model predicted a decrease
  IterationCap,  ///< maxIterations reached while still improving
};

/// "converged", "stalled" or "iteration cap".
const char* fitStatusName(FitStatus status);

/// One row of the history. Row 0 describes the initial curve (step 0).
struct FitIteration {
  int iteration = 0;
  double objective = 0.0;    ///< E(P) after the iteration (world units squared)
  double rmsDistance = 0.0;  ///< RMS of the true distances (sensors or data points), world units
  double maxDistance = 0.0;  ///< their maximum, world units
  double stepLength = 0.0;   ///< largest control-point move of the accepted step, world units
  double stepScale = 1.0;    ///< line-search factor of the accepted step (1 = full step)
  double damping = 0.0;      ///< Levenberg-Marquardt damping used (relative), 0 when none
};

/// The outcome of a fit.
struct CurveFitResult {
  BSplineCurve curve;  ///< the final curve (same knots as the initial one)
  FitStatus status = FitStatus::IterationCap;
  std::string reason;                  ///< one line saying why it stopped
  std::vector<FitIteration> history;   ///< row 0 = initial curve, then one row per iteration
  std::vector<BSplineCurve> iterates;  ///< with keepIterates: initial curve, then every iterate
  int iterations() const { return static_cast<int>(history.size()) - 1; }
};

}  // namespace d2vdb
