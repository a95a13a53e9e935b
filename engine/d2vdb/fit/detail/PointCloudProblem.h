// Internal: SDM II's side of the fit loop (detail/FitLoop.h) for a curve and a point cloud:
// sensors at the data points' footpoints on the active curve, their error terms and the exact
// second-order terms of the squared distance to the moving curve (Wang, Pottmann and Liu, "Fitting
// B-spline curves to point clouds by curvature-based squared distance minimization", 2006).
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/fit/detail/FitLoop.h"
#include "d2vdb/fit/detail/SensorBasis.h"
#include "d2vdb/measure/PointProjection.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb::detail {

/// curveApproximantAt() (PointCloudFitter.h) from the curve's point and derivatives at the
/// footpoint; `endPoint`: the footpoint is an end of an open curve.
Approximant curveApproximantFrom(const CurveDerivatives& derivatives, bool endPoint, int dimension,
                                 const Eigen::Vector3d& dataPoint);

/// The point-cloud fitting problem (fitCurveToPoints()). measure() projects every data point
/// onto the candidate curve (CurveProjector::nearest, hinted by the accepted footpoints);
/// linearize() makes one sensor per data point at its accepted footpoint with the error term of
/// options.method, plus for SDM (options.exactSecondOrder) two rank-one second-order terms per
/// data point: with r = C(t) - X, B and B' the basis values and derivatives at t,
///   u = B (x) C' + B' (x) r, D = |C'|^2 + r . C'', v = B (x) T:
///   -(u . c)^2 / D + (1 - w) (v . c)^2,
/// so that form + terms is the exact Hessian of |C(t(P)) - X|^2 in the footpoint's control points
/// (w the SDM form's tangential weight; none where D < 0.1 |C'|^2 or t is an open curve's end).
/// Open curves also get one PDM term per end, pulling it to its nearest data point. The data
/// points must outlive the problem; measure() must precede the first linearize().
class PointCloudProblem final : public FitProblem {
 public:
  PointCloudProblem(const BSplineCurve& initial, const std::vector<Eigen::Vector3d>& points,
                    const CurveFitOptions& options);

  void linearize(const std::vector<Eigen::Vector3d>& controlPoints,
                 FitLinearization& linearization) override;
  DataError measure(const std::vector<Eigen::Vector3d>& controlPoints) override;
  void accept() override { current_.swap(candidate_); }
  bool offersCorrection() const override { return footpointCorrection_; }
  /// With options.footpointCorrection (SDM with the exact second-order terms): the squared
  /// distances of the data points to the candidate curve at their footpoints on it, held fixed
  /// (and of the open curve's ends to their nearest data points), as PDM forms: for fixed
  /// parameters the control points enter linearly, so the loop's correction is the exact
  /// least-squares fit for the parametrisation the step reached: the linear variables solved
  /// exactly for the nonlinear ones, as in Golub and Pereyra's variable projection ("The
  /// differentiation of pseudo-inverses and nonlinear least squares problems whose variables
  /// separate", 1973), and the least-squares step of parameter-correction fitting (Hoschek,
  /// "Intrinsic parametrization for approximation", 1988), here after each Newton step.
  bool correction(const std::vector<Eigen::Vector3d>& controlPoints,
                  FitLinearization& correction) override;

 private:
  struct Footpoint {
    SegmentPoint location;
    double parameter = 0.0;
    double squaredDistance = 0.0;
  };

  /// Index of the data point nearest to x (lowest index on ties); a linear scan.
  std::size_t nearestDataPoint(const Eigen::Vector3d& x) const;

  const std::vector<Eigen::Vector3d>& points_;
  BSplineCurve curve_;  // the net linearize() was last called with
  FitMethod method_;
  double pdmWeight_;
  bool exactSecondOrder_;
  bool footpointCorrection_;
  std::optional<SensorBasis> basis_;
  std::optional<SensorBasis> correctionBasis_;
  std::vector<Footpoint> current_;
  std::vector<Footpoint> candidate_;
  std::vector<std::size_t> candidateEnds_;  // nearest data points of the candidate's open ends
};

}  // namespace d2vdb::detail
