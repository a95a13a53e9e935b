// The options every squared-distance fitter shares (curves: CurveFit.h; surfaces: SurfaceFit.h).
#pragma once

#include "d2vdb/core/Progress.h"
#include "d2vdb/fit/FitMethod.h"

namespace d2vdb {

/// How a fit is run, whatever the spline. Distances are world units; the objective is
///   E(P) = mean_k F_k(x_k(P)) + smoothness * B(P) + stretch * S(P)
/// with F_k the true squared distance of sensor k (to a target) or of data point k (to the
/// spline), B the spline's bending energy and S its stretching energy over its parameters
/// normalised to [0, 1] (curves: int |x''|^2 and int |x'|^2, CurveFitOptions; surfaces: the
/// thin-plate and membrane energies, SurfaceFitOptions). Both weights are dimensionless.
///
/// The fit's precision is rms * sqrt(n / N): the RMS distance times the square root of control
/// points per term, the statistical uncertainty of a least-squares fit with that much freedom
/// (for noisy data, the noise floor).
struct FitOptions {
  FitMethod method = FitMethod::SDM;
  /// Weight of the PDM term in FitMethod::TDMPlusPDM.
  double pdmWeight = 0.01;
  /// Weight of the bending energy. It holds the sensors' parametrisation (the spline can slide
  /// along the target without changing the distances) and keeps spans or cells without data from
  /// folding, but biases the fit: it pulls curved parts inward (a circle of radius R by about
  /// 1560 * smoothness * R; a surface flattens and shrinks). Negative (the default) = automatic:
  /// every iteration the weight is chosen so that the shift it causes in the model's minimiser
  /// (measured across the target at the sensors) is automaticSmoothingBias times the fit's
  /// resolution: strong while the spline is far off, a fixed fraction of the noise floor (or of
  /// the approximation floor, for exact data) at convergence. The history records the weight of
  /// each iteration.
  double smoothness = -1.0;
  /// With automatic smoothness: the bending term's shift as a fraction of the fit's precision.
  double automaticSmoothingBias = 0.25;
  /// Weight of the stretching energy (0 = off).
  double stretch = 0.0;
  /// Step regularisation: the weight rho of the term rho m0 / g0 sum_a c_a^T R c_a that each
  /// iteration's quadratic model adds for the displacement c, with R the bending matrix (curves:
  /// the Gram matrix of order min(degree, 2); surfaces: the thin-plate matrix, the membrane matrix
  /// for degree (1, 1)), g0 its mean diagonal and m0 that of the data term. Damps rough and
  /// tangential (reparametrising) moves without biasing the fit, at the price of slower
  /// convergence; 0 (default) = off.
  double stepSmoothness = 0.0;
  /// SDM: add exact second-order terms of the squared distance that the SDM error terms leave
  /// out, blended in by a trust-region rule, so that the spline's sliding along itself converges
  /// like Newton's method instead of linearly. On point clouds they say how each footpoint's
  /// parameters follow the control points (curves and surfaces); on a target, for surfaces, they
  /// are the curvature terms the clamped SDM form drops on the concave side. false = the plain SDM
  /// terms of Wang, Pottmann and Liu (2006).
  bool exactSecondOrder = true;
  /// Iteration cap.
  int maxIterations = 100;
  /// Converged when the RMS distance falls to this (world units; 0 = not used).
  double distanceTolerance = 0.0;
  /// Converged when an iteration's largest sensor move across the target and RMS change, each
  /// extrapolated at its rate of convergence, are at most the geometric tolerance
  /// max(stepTolerance x size, moveTolerance x the fit's precision, 1/100 of the target's
  /// resolution), with size the largest side of the initial control points' bounding box.
  double stepTolerance = 1e-9;
  double moveTolerance = 0.1;
  /// Converged when an accepted step lowers the objective by less than this fraction of it;
  /// 0 (default) = not used (the geometric test decides).
  double objectiveTolerance = 0.0;
  /// Initial Levenberg-Marquardt damping for TDM, relative to the mean diagonal of the system;
  /// divided by 3 after a full step, multiplied by 10 when a step fails to decrease E.
  double initialDamping = 1e-3;
  /// Keep every iterate in the result's `iterates` (for drawing).
  bool keepIterates = false;
  /// Progress: stage "fit", fraction = iteration / maxIterations.
  ProgressCallback progress;
};

}  // namespace d2vdb
