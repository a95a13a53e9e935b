// Options, history and result of the B-spline surface fitters (SurfaceFitter.h).
#pragma once

#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/fit/FitHistory.h"
#include "d2vdb/fit/FitMethod.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// How a surface fit is run. Distances are world units; the objective is
///   E(P) = mean_k F_k(x_k(P)) + smoothness * T(P) + stretch * M(P)
/// with F_k the true squared distance of sensor k (SDM I) or of data point k (SDM II), T the
/// thin-plate energy int int (|x_ss|^2 + 2 |x_st|^2 + |x_tt|^2) ds dt and M the membrane energy
/// int int (|x_s|^2 + |x_t|^2) ds dt over the parameters normalised to [0, 1]^2
/// (ThinPlateMatrix.h). Both weights are dimensionless (per unit of the data term's squared
/// length over the squared size of the surface).
struct SurfaceFitOptions {
  FitMethod method = FitMethod::SDM;
  /// Sensors per knot span in each direction (SDM I): perSpan^2 per knot cell, plus the boundary
  /// lines of open directions. SDM II uses one sensor per data point.
  int sensorsPerSpan = 6;
  /// Weight of the PDM term in FitMethod::TDMPlusPDM.
  double pdmWeight = 0.01;
  /// Weight of the thin-plate energy. It holds the sensors' parametrisation (the surface can
  /// slide along the target without changing the distances) and keeps cells without data from
  /// folding, but biases the fit: it flattens and shrinks. Negative (the default) = automatic, as
  /// for curves (CurveFitOptions::smoothness): every iteration the weight is chosen so that the
  /// shift it causes in the model's minimiser (measured across the target at the sensors) is
  /// automaticSmoothingBias times the fit's resolution rms * sqrt(n / N) (n control points, N
  /// sensors or data points): strong while the surface is far off, a fixed fraction of the noise
  /// floor (or of the approximation floor, for exact data) at convergence. The history records
  /// the weight of each iteration.
  double smoothness = -1.0;
  /// With automatic smoothness: the thin-plate term's shift as a fraction of the fit's resolution.
  double automaticSmoothingBias = 0.25;
  /// Weight of the membrane energy (0 = off).
  double stretch = 0.0;
  /// Step regularisation: rho of QuadraticModel::setStepRegularizer with the thin-plate matrix
  /// of the displacement (the membrane matrix for degree (1, 1)), relative to the mean diagonal of
  /// the data term. Damps rough and tangential moves without biasing the fitted surface, at the
  /// price of slower convergence; 0 (default) = off.
  double stepSmoothness = 0.0;
  /// SDM on point clouds: add the exact second-order terms of the squared distance to the moving
  /// surface (how each footpoint's parameters (u, v) follow the control points) to the SDM error
  /// terms, blended in by a trust-region rule, so that the surface's sliding along itself
  /// converges like Newton's method. false = the plain SDM terms.
  bool exactSecondOrder = true;
  /// Iteration cap.
  int maxIterations = 100;
  /// Converged when the RMS distance falls to this (world units; 0 = not used).
  double distanceTolerance = 0.0;
  /// Converged when an iteration's largest sensor move across the target and RMS change, each
  /// extrapolated at its rate of convergence, are at most the geometric tolerance
  /// max(stepTolerance x size, moveTolerance x the fit's resolution, 1/100 of the target's
  /// resolution), with size the largest side of the initial control points' bounding box.
  double stepTolerance = 1e-9;
  double moveTolerance = 0.1;
  /// Converged when an accepted step lowers the objective by less than this fraction of it;
  /// 0 (default) = not used (the geometric test decides).
  double objectiveTolerance = 0.0;
  /// Initial Levenberg-Marquardt damping for TDM, relative to the mean diagonal of the system.
  double initialDamping = 1e-3;
  /// Keep every iterate in SurfaceFitResult::iterates.
  bool keepIterates = false;
  /// Progress: stage "fit", fraction = iteration / maxIterations.
  ProgressCallback progress;
};

/// The outcome of a surface fit (FitStatus and FitIteration as for curves).
struct SurfaceFitResult {
  BSplineSurface surface;  ///< the final surface (same knots as the initial one)
  FitStatus status = FitStatus::IterationCap;
  std::string reason;                    ///< one line saying why it stopped
  std::vector<FitIteration> history;     ///< row 0 = initial surface, then one row per iteration
  std::vector<BSplineSurface> iterates;  ///< with keepIterates: initial surface, then every iterate
  int iterations() const { return static_cast<int>(history.size()) - 1; }
};

}  // namespace d2vdb
