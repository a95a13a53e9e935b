#include "d2vdb/fit/CurveFitter.h"

#include <memory>

#include "d2vdb/fit/detail/CurveFitLoop.h"
#include "d2vdb/fit/detail/SensorBasis.h"
#include "d2vdb/fit/detail/TargetProblem.h"

namespace d2vdb {
namespace {

// Sensors at fixed parameters, approximants from the target, the error terms of the method.
class CurveTargetProblem final : public detail::TargetProblem {
 public:
  CurveTargetProblem(const BSplineCurve& initial, const SquaredDistanceTarget& target,
                     const CurveFitOptions& options)
      : TargetProblem(
            target,
            std::make_unique<detail::SensorBasis>(
                initial, detail::uniformSensorParameters(initial, options.sensorsPerSpan)),
            options.method, options.pdmWeight) {}

  void linearize(const std::vector<Eigen::Vector3d>& controlPoints,
                 detail::FitLinearization& linearization) override {
    linearization.secondOrder.reset(sensors().sensorCount(), 0);
    setForms(approximantsAt(controlPoints), linearization);
  }
};

}  // namespace

CurveFitResult fitCurve(const BSplineCurve& initial, const SquaredDistanceTarget& target,
                        const CurveFitOptions& options) {
  detail::validateCurveFit(initial, options);
  CurveTargetProblem problem(initial, target, options);
  problem.requireCovered(initial.controlPoints(), "curve");
  // The one-sided distance (sensors to target) does not hold the ends of an open curve, which a
  // bending term would pull in along the target: automatic smoothing means none there.
  CurveFitOptions effective = options;
  if (effective.smoothness < 0.0 && !initial.isClosed()) effective.smoothness = 0.0;
  return detail::runCurveFit(initial, effective, problem);
}

}  // namespace d2vdb
