// Options, history and result of the B-spline surface fitters (SurfaceFitter.h).
#pragma once

#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/fit/FitMethod.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// The thin-plate weight the automatic smoothing converges with first (see
/// SurfaceFitOptions::smoothness).
inline constexpr double kAutoSurfaceSmoothness = 1e-7;

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
  /// Weight of the thin-plate energy. It regularises the tangential freedom of the sensors (the
  /// surface can slide along the target without changing the distances) but biases the fit: it
  /// flattens and shrinks. Negative (the default) = automatic: the fit first converges with
  /// kAutoSurfaceSmoothness (to a relative objective decrease below 1e-4), which fixes the
  /// parametrisation, then continues from there without smoothing, its steps damped by the
  /// thin-plate energy of the displacement (the step regulariser of QuadraticModel, relative
  /// weight 1e-3 unless stepSmoothness says otherwise), which vanishes at convergence: the final
  /// surface minimises the data term alone. The history runs on through both phases.
  double smoothness = -1.0;
  /// Weight of the membrane energy (0 = off).
  double stretch = 0.0;
  /// Step regularisation: rho of QuadraticModel::setStepRegularizer with the thin-plate matrix
  /// of the displacement (the membrane matrix for degree (1, 1)), relative to the mean diagonal of
  /// the data term. Damps rough and tangential moves without biasing the fitted surface.
  /// 0 (default) = off, except in the second automatic phase (see smoothness).
  double stepSmoothness = 0.0;
  /// Iteration cap (both automatic phases together).
  int maxIterations = 100;
  /// Converged when the RMS distance falls to this (world units; 0 = not used).
  double distanceTolerance = 0.0;
  /// Converged when the largest control-point move of an iteration is below this fraction of the
  /// initial surface's size (largest side of its control points' bounding box).
  double stepTolerance = 1e-9;
  /// Converged when an accepted step lowers the objective by less than this fraction of it.
  double objectiveTolerance = 1e-8;
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
