// Internal: the fit loop's problem (detail/FitLoop.h) for a spline fitted to a
// SquaredDistanceTarget through sensors at fixed parameters (SDM I): curves (CurveFitter.h) and
// surfaces (SurfaceFitter.h) differ only in their sensors and in the terms they build from the
// approximants.
#pragma once

#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/field/SquaredDistanceTarget.h"
#include "d2vdb/fit/FitMethod.h"
#include "d2vdb/fit/detail/FitLoop.h"
#include "d2vdb/fit/detail/SensorMap.h"

namespace d2vdb::detail {

/// measure() finds, in one parallel pass, the sensor positions, checks them against the target's
/// domain (a sensor outside it, or not finite, makes the net invalid), and takes the target's
/// approximants there and the squared distances they give (as
/// SquaredDistanceTarget::squaredDistanceAt() computes them); it keeps the approximants so that
/// linearize() of an accepted net need not query the target again. Deterministic for any thread
/// count. The target must outlive the problem.
class TargetProblem : public FitProblem {
 public:
  TargetProblem(const SquaredDistanceTarget& target, std::unique_ptr<const SensorMap> sensors,
                FitMethod method, double pdmWeight);

  /// The sensors (fixed linear maps from the control points).
  const SensorMap& sensors() const { return *sensors_; }
  double resolvedLength() const override { return target_.resolvedLength(); }
  DataError measure(const std::vector<Eigen::Vector3d>& controlPoints) override;
  void accept() override;

  /// Throws InputError naming the first sensor of the net `controlPoints` that lies outside the
  /// target's domain, and the domain; `spline` names the net ("curve", "surface").
  void requireCovered(const std::vector<Eigen::Vector3d>& controlPoints,
                      const std::string& spline) const;

 protected:
  /// The approximants at the sensors of `controlPoints`: the ones measure() found when it is the
  /// accepted net (handed over once), else the target's. Valid until the next call.
  const std::vector<Approximant>& approximantsAt(const std::vector<Eigen::Vector3d>& controlPoints);
  /// linearization.basis = the sensors and forms[k] = fitForm(approximants[k], method, pdmWeight),
  /// in parallel.
  void setForms(const std::vector<Approximant>& approximants,
                FitLinearization& linearization) const;

  FitMethod method() const { return method_; }

 private:
  const SquaredDistanceTarget& target_;
  Eigen::AlignedBox3d domain_;
  std::unique_ptr<const SensorMap> sensors_;
  FitMethod method_;
  double pdmWeight_;
  // Approximants of the last measured and of the accepted net, with its control points (an
  // empty control-point list: none valid).
  std::vector<Eigen::Vector3d> measuredControlPoints_, acceptedControlPoints_;
  std::vector<Approximant> measuredApproximants_, acceptedApproximants_;
  bool acceptedValid_ = false;
  std::vector<double> squared_;
};

}  // namespace d2vdb::detail
