#include "d2vdb/fit/CurveFitter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/fit/SensorBasis.h"
#include "d2vdb/fit/detail/FitLoop.h"

namespace d2vdb {
namespace {

// Sensors at fixed parameters, approximants from the target.
class TargetProblem final : public detail::FitProblem {
 public:
  TargetProblem(const BSplineCurve& initial, const SquaredDistanceTarget& target, int perSpan)
      : target_(target),
        domain_(target.domain()),
        basis_(initial, uniformSensorParameters(initial, perSpan)) {}

  const SensorBasis& basis() const { return basis_; }
  const SensorBasis* fixedBasis() const override { return &basis_; }
  double resolution() const override { return target_.resolution(); }

  void linearize(const BSplineCurve& curve, const CurveFitOptions& options,
                 std::vector<double>& parameters, std::vector<QuadraticForm>& forms) override {
    parameters = basis_.parameters();
    const std::vector<Eigen::Vector3d> sensors = basis_.positions(curve.controlPoints());
    const std::vector<Approximant> approximants = target_.approximantsAt(sensors);
    forms.resize(approximants.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, approximants.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t k = range.begin(); k != range.end(); ++k) {
                          forms[k] = fitForm(approximants[k], options.method, options.pdmWeight);
                        }
                      });
  }

  detail::DataError measure(const BSplineCurve& curve) override {
    const std::vector<Eigen::Vector3d> sensors = basis_.positions(curve.controlPoints());
    detail::DataError error;
    error.count = static_cast<int>(sensors.size());
    for (const Eigen::Vector3d& x : sensors) {
      if (!domain_.contains(x) || !x.allFinite()) {
        error.valid = false;
        return error;
      }
    }
    std::vector<double> squared(sensors.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sensors.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t k = range.begin(); k != range.end(); ++k) {
                          squared[k] = target_.squaredDistanceAt(sensors[k]);
                        }
                      });
    for (const double value : squared) {  // fixed order: deterministic sum
      error.sum += value;
      error.maxSquared = std::max(error.maxSquared, value);
    }
    return error;
  }

 private:
  const SquaredDistanceTarget& target_;
  Eigen::AlignedBox3d domain_;
  SensorBasis basis_;
};

std::string pointText(const Eigen::Vector3d& p) {
  std::ostringstream text;
  text << '(' << p.x() << ", " << p.y() << ", " << p.z() << ')';
  return text.str();
}

}  // namespace

CurveFitResult fitCurve(const BSplineCurve& initial, const SquaredDistanceTarget& target,
                        const CurveFitOptions& options) {
  detail::validateFitOptions(options);
  detail::requireNonDegenerate(initial, "the initial curve");
  TargetProblem problem(initial, target, options.sensorsPerSpan);
  const Eigen::AlignedBox3d domain = target.domain();
  const std::vector<Eigen::Vector3d> sensors = problem.basis().positions(initial.controlPoints());
  for (std::size_t k = 0; k < sensors.size(); ++k) {
    if (!domain.contains(sensors[k])) {
      const Eigen::Vector3d outside =
          (sensors[k] - sensors[k].cwiseMax(domain.min()).cwiseMin(domain.max())).cwiseAbs();
      throw InputError("the target (" + target.describe() +
                       ") does not cover the initial curve: "
                       "sensor " +
                       std::to_string(k) + " at " + pointText(sensors[k]) + " lies " +
                       std::to_string(outside.norm()) + " outside its domain " +
                       pointText(domain.min()) + " - " + pointText(domain.max()) +
                       "; start from a curve inside the domain or build the target with more "
                       "padding");
    }
  }
  return detail::runFitLoop(initial, options, problem);
}

}  // namespace d2vdb
