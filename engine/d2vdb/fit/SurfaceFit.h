// Options and result of the B-spline surface fitters (SurfaceFitter.h).
#pragma once

#include <vector>

#include "d2vdb/core/ResourceBudget.h"
#include "d2vdb/fit/FitHistory.h"
#include "d2vdb/fit/FitOptions.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// How a surface fit is run (FitOptions): the bending energy is the thin-plate energy
/// T = int int (|x_ss|^2 + 2 |x_st|^2 + |x_tt|^2) ds dt and the stretching energy the membrane
/// energy M = int int (|x_s|^2 + |x_t|^2) ds dt over the parameters normalised to [0, 1]^2;
/// F_k is the true squared distance of sensor k (SDM I, fitSurface) or of data point k (SDM II,
/// fitSurfaceToPoints). A surface of degree (1, 1) has no thin-plate energy
/// of its own (only its twist): it gets no bending term.
struct SurfaceFitOptions : FitOptions {
  /// Sensors per knot span in each direction (SDM I): perSpan^2 per knot cell, plus the boundary
  /// lines of open directions. SDM II uses one sensor per data point.
  int sensorsPerSpan = 6;
  /// fitSurface (SDM I): after 8 iterations (or when the fit stops before), if spreading the
  /// surface's parameters by mean chord length moves one by more than 1 % of its domain, the
  /// surface is re-parametrised that way (same knots and shape: the control points refitted by
  /// least squares) and the fit continues from there once, within the same iteration cap (a fit
  /// that had stopped by itself is kept when the restart ends no closer to the target). The
  /// squared distance does not see how the parameters are spread along the target, so a fit
  /// whose first steps crowded them (e.g. a torus started with wrong radii) otherwise relaxes
  /// only very slowly, and a crowded spread approximates worse. false = one run. Not used by
  /// fitSurfaceToPoints.
  bool reparametrize = true;
  /// The memory budget both fitters check their estimate against before allocating anything
  /// (enforceSurfaceFitBudget(), SurfaceFitter.h); only maxMemoryBytes is used.
  ResourceBudget budget;
};

/// The outcome of a surface fit.
struct SurfaceFitResult : FitReport {
  BSplineSurface surface;                ///< the final surface (same knots as the initial one)
  std::vector<BSplineSurface> iterates;  ///< with keepIterates: initial surface, then every iterate
};

}  // namespace d2vdb
