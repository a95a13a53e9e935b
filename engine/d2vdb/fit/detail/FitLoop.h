// Internal: the iteration shared by the curve fitters (sensor model, solve, step control,
// stopping). Not part of the public API.
#pragma once

#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/fit/SensorBasis.h"

namespace d2vdb::detail {

/// The true data error of a curve: sum and maximum of the squared distances over `count` terms.
/// valid = false when the curve left the region where the target answers.
struct DataError {
  double sum = 0.0;
  double maxSquared = 0.0;
  int count = 0;
  bool valid = true;
};

/// What a fitter supplies to the loop.
class FitProblem {
 public:
  virtual ~FitProblem() = default;
  /// The sensor parameters and their quadratic forms (world units) at the current curve.
  virtual void linearize(const BSplineCurve& curve, const CurveFitOptions& options,
                         std::vector<double>& parameters, std::vector<QuadraticForm>& forms) = 0;
  /// The true data error of a candidate curve (remembers what it needs for accept()).
  virtual DataError measure(const BSplineCurve& curve) = 0;
  /// The last measured candidate became the current curve.
  virtual void accept() {}
  /// The sensors' basis when their parameters never change (linearize() always returns
  /// basis->parameters()), so the loop need not rebuild it each iteration; else null.
  virtual const SensorBasis* fixedBasis() const { return nullptr; }
  /// The target's resolution (SquaredDistanceTarget::resolution()); 0 for exact data.
  virtual double resolution() const { return 0.0; }
};

/// Runs the fit from `initial` (validated by the caller; the loop checks the options and that
/// the control points do not all coincide, InputError otherwise). problem.measure(initial) must
/// be valid (InputError otherwise).
CurveFitResult runFitLoop(const BSplineCurve& initial, const CurveFitOptions& options,
                          FitProblem& problem);

/// Throws InputError when the options are out of range (negative weights, no iterations, ...).
void validateFitOptions(const CurveFitOptions& options);

/// Throws InputError when all control points of `curve` coincide (to 1e-12 of their magnitude).
void requireNonDegenerate(const BSplineCurve& curve, const char* what);

}  // namespace d2vdb::detail
