// Why a squared-distance fit stopped and what each of its iterations did: shared by the fitters
// of curves (CurveFit.h), surfaces (SurfaceFit.h) and any other control net run by the same
// iteration.
#pragma once

#include <string>
#include <vector>

namespace d2vdb {

/// Why a fit stopped.
enum class FitStatus {
  Converged,     ///< the control net stopped moving (its largest move fell below the geometric
                 ///< tolerance), the RMS distance reached the distance tolerance, the objective
                 ///< no longer changed beyond rounding, or no step lowered the objective although
                 ///< the model's step was below what the target resolves (1/100 of a field's
                 ///< voxel)
  Stalled,       ///< no step lowered the objective although the model predicted a decrease
                 ///< (line search, damping and second-order fallback exhausted)
  IterationCap,  ///< the iteration cap was reached while the net was still moving
};

/// "converged", "stalled" or "iteration cap".
const char* fitStatusName(FitStatus status);

/// One row of a fit's history. Row 0 describes the initial control net (step 0).
struct FitIteration {
  int iteration = 0;
  double objective = 0.0;    ///< E(P) after the iteration with that iteration's smoothing weight
                             ///< (world units squared)
  double rmsDistance = 0.0;  ///< RMS of the true distances (sensors or data points), world units
  double maxDistance = 0.0;  ///< their maximum, world units
  double stepLength = 0.0;   ///< largest control-point move of the accepted step, world units
  double targetMove = 0.0;   ///< largest sensor move of the step across the target (in the error
                             ///< terms' metric: for SDM and TDM the normal move), world units
  double stepScale = 1.0;    ///< line-search factor of the accepted step (1 = full step; above
                             ///< 1 when a corrected step was lengthened)
  double damping = 0.0;      ///< Levenberg-Marquardt damping used (relative), 0 when none
  double smoothness = 0.0;   ///< bending weight lambda2 of the iteration (automatic or fixed)
  double secondOrderWeight = 0.0;  ///< share (0..1) of the fitter's exact second-order terms in
                                   ///< the step's model (SDM II; 0 = the plain SDM form)
};

/// Why a fit stopped and what each iteration did; CurveFitResult and SurfaceFitResult add the
/// fitted spline and its iterates.
struct FitReport {
  FitStatus status = FitStatus::IterationCap;
  std::string reason;                 ///< one line saying why it stopped
  std::vector<FitIteration> history;  ///< row 0 = initial control net, then one row per iteration
  /// Number of iterations run (history rows after the initial one).
  int iterations() const { return static_cast<int>(history.size()) - 1; }
};

}  // namespace d2vdb
