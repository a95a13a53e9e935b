// Internal: the iteration shared by the curve and surface fitters (sensor model, solve, step
// control, stopping). Not part of the public API.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/fit/SensorMap.h"
#include "d2vdb/fit/SurfaceFit.h"
#include "d2vdb/spline/BSplineCurve.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb::detail {

/// The true data error of a curve or surface: sum and maximum of the squared distances over
/// `count` terms. valid = false when the spline left the region where the target answers.
struct DataError {
  double sum = 0.0;
  double maxSquared = 0.0;
  int count = 0;
  bool valid = true;
};

/// The types that go with a spline in the loop: its sensor parameter, options and result.
template <typename Spline>
struct FitTypes;
template <>
struct FitTypes<BSplineCurve> {
  using Parameter = double;
  using Options = CurveFitOptions;
  using Result = CurveFitResult;
};
template <>
struct FitTypes<BSplineSurface> {
  using Parameter = Eigen::Vector2d;
  using Options = SurfaceFitOptions;
  using Result = SurfaceFitResult;
};

/// What a fitter supplies to the loop, for a curve or a surface.
template <typename Spline>
class FitProblemFor {
 public:
  using Parameter = typename FitTypes<Spline>::Parameter;
  using Options = typename FitTypes<Spline>::Options;

  virtual ~FitProblemFor() = default;
  /// The sensor parameters and their quadratic forms (world units) at the current spline.
  virtual void linearize(const Spline& spline, const Options& options,
                         std::vector<Parameter>& parameters, std::vector<QuadraticForm>& forms) = 0;
  /// The true data error of a candidate spline (remembers what it needs for accept()).
  virtual DataError measure(const Spline& spline) = 0;
  /// The last measured candidate became the current spline.
  virtual void accept() {}
  /// The sensors' basis when their parameters never change (linearize() always returns its
  /// parameters), so the loop need not rebuild it each iteration; else null.
  virtual const SensorMap* fixedBasis() const { return nullptr; }
  /// The target's resolution (SquaredDistanceTarget::resolution()); 0 for exact data.
  virtual double resolution() const { return 0.0; }
};

/// The curve fitters' problem.
using FitProblem = FitProblemFor<BSplineCurve>;
/// The surface fitters' problem.
using SurfaceFitProblem = FitProblemFor<BSplineSurface>;

/// Runs the fit from `initial` (validated by the caller; the loop checks the options and that
/// the control points do not all coincide, InputError otherwise). problem.measure(initial) must
/// be valid (InputError otherwise).
CurveFitResult runFitLoop(const BSplineCurve& initial, const CurveFitOptions& options,
                          FitProblem& problem);
/// The same loop for a surface.
SurfaceFitResult runFitLoop(const BSplineSurface& initial, const SurfaceFitOptions& options,
                            SurfaceFitProblem& problem);

/// Throws InputError when the options are out of range (negative weights, no iterations, ...).
void validateFitOptions(const CurveFitOptions& options);
/// Throws InputError when the options are out of range.
void validateFitOptions(const SurfaceFitOptions& options);

/// Throws InputError when all control points of `curve` coincide (to 1e-12 of their magnitude).
void requireNonDegenerate(const BSplineCurve& curve, const char* what);
/// Throws InputError when all control points of `surface` coincide.
void requireNonDegenerate(const BSplineSurface& surface, const char* what);

}  // namespace d2vdb::detail
