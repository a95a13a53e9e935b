// Options and result of the B-spline curve fitters (CurveFitter.h, PointCloudFitter.h).
#pragma once

#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/fit/FitHistory.h"
#include "d2vdb/fit/FitMethod.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// How a fit is run. Distances are world units; the objective is
///   E(P) = mean_k F_k(x_k(P)) + smoothness * int |x''(u)|^2 du + stretch * int |x'(u)|^2 du
/// with u the curve parameter normalised to [0, 1] (SmoothingMatrix.h) and F_k the true squared
/// distance of sensor k (CurveFitter) or of data point k (PointCloudFitter). Both smoothing
/// weights are dimensionless; for a circle of radius R the bending term is 16 pi^4 R^2
/// smoothness, i.e. it shrinks the fit by about 1560 * smoothness * R.
///
/// The fit's resolution is rms * sqrt(n / N): the RMS distance times the square root of control
/// points per term, the statistical uncertainty of a least-squares fit with that much freedom
/// (for noisy data, the noise floor).
struct CurveFitOptions {
  FitMethod method = FitMethod::SDM;
  /// Sensors per knot span (CurveFitter only; PointCloudFitter uses one per data point).
  int sensorsPerSpan = 8;
  /// Weight of the PDM term in FitMethod::TDMPlusPDM.
  double pdmWeight = 0.01;
  /// lambda2: weight of the bending energy int |x''|^2 of the curve. It holds the curve's
  /// parametrisation and keeps spans without data (and thick or noisy clouds) from folding, but
  /// biases the fit: it pulls curved parts inward (a circle by about 1560 * smoothness * R; the
  /// energy grows with the fourth power of the waviness). Negative (the default) = automatic:
  /// every iteration the weight is chosen so that the shift it causes in the model's minimiser
  /// (measured at the sensors) is automaticSmoothingBias times the fit's resolution: strong while
  /// the curve is far off, a fixed fraction of the noise floor at convergence. The history
  /// records the weight of each iteration.
  double smoothness = -1.0;
  /// With automatic smoothness: the bending term's shift as a fraction of the fit's resolution.
  double automaticSmoothingBias = 0.25;
  /// lambda1: weight of the stretching energy int |x'|^2.
  double stretch = 0.0;
  /// Step regularisation: rho of QuadraticModel::setStepRegularizer with the bending Gram matrix
  /// of the displacement, relative to the mean diagonal of the data term. Damps rough and
  /// tangential (reparametrising) moves without biasing the fitted curve, at the price of slower
  /// convergence; 0 (default) = off.
  double stepSmoothness = 0.0;
  /// SDM on point clouds: add the exact second-order terms of the squared distance to the
  /// moving curve (how each footpoint's parameter follows the control points) to the SDM error
  /// terms, blended in by a trust-region rule, so that the curve's sliding along itself
  /// converges like Newton's method instead of linearly. false = the plain SDM terms of Wang,
  /// Pottmann and Liu (2006).
  bool exactSecondOrder = true;
  /// Iteration cap.
  int maxIterations = 100;
  /// Converged when the RMS distance falls to this (world units; 0 = not used).
  double distanceTolerance = 0.0;
  /// Converged when an iteration's largest control-point move and RMS change are at most the
  /// geometric tolerance max(stepTolerance x size, moveTolerance x the fit's resolution, 1/100 of
  /// the target's resolution), with size the largest side of the initial control points'
  /// bounding box.
  double stepTolerance = 1e-9;
  double moveTolerance = 0.1;
  /// Converged when an accepted step lowers the objective by less than this fraction of it;
  /// 0 (default) = not used (the geometric test decides).
  double objectiveTolerance = 0.0;
  /// Initial Levenberg-Marquardt damping for TDM, relative to the mean diagonal of the system;
  /// divided by 3 after a full step, multiplied by 10 when a step fails to decrease E.
  double initialDamping = 1e-3;
  /// Keep every iterate in CurveFitResult::iterates (for drawing).
  bool keepIterates = false;
  /// Progress: stage "fit", fraction = iteration / maxIterations.
  ProgressCallback progress;
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
