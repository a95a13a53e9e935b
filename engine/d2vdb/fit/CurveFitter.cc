#include "d2vdb/fit/CurveFitter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/fit/SensorBasis.h"
#include "d2vdb/fit/detail/CurveFitLoop.h"

namespace d2vdb {
namespace {

// Sensors at fixed parameters, approximants from the target.
class TargetProblem final : public detail::FitProblem {
 public:
  TargetProblem(const BSplineCurve& initial, const SquaredDistanceTarget& target,
                const CurveFitOptions& options)
      : target_(target),
        domain_(target.domain()),
        basis_(initial, uniformSensorParameters(initial, options.sensorsPerSpan)),
        method_(options.method),
        pdmWeight_(options.pdmWeight) {}

  const SensorBasis& basis() const { return basis_; }
  double resolution() const override { return target_.resolution(); }

  void linearize(const std::vector<Eigen::Vector3d>& controlPoints,
                 detail::FitLinearization& linearization) override {
    linearization.basis = &basis_;
    linearization.secondOrder.reset(basis_.sensorCount(), 0);
    std::vector<QuadraticForm>& forms = linearization.forms;
    // The loop linearises the net it last accepted, whose forms measure() computed.
    if (controlPoints == acceptedControlPoints_ && acceptedFormsValid_) {
      forms.swap(acceptedForms_);
      acceptedFormsValid_ = false;
      return;
    }
    const std::vector<Approximant> approximants =
        target_.approximantsAt(basis_.positions(controlPoints));
    forms.resize(approximants.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, approximants.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t k = range.begin(); k != range.end(); ++k) {
                          forms[k] = fitForm(approximants[k], method_, pdmWeight_);
                        }
                      });
  }

  // One parallel pass: sensor positions, the domain check, the approximants there, the squared
  // distances they give (as SquaredDistanceTarget::squaredDistanceAt() computes them) and the
  // fitting forms (kept for linearize() should this net be accepted).
  detail::DataError measure(const std::vector<Eigen::Vector3d>& controlPoints) override {
    const int count = basis_.sensorCount();
    measuredForms_.resize(static_cast<std::size_t>(count));
    squared_.resize(static_cast<std::size_t>(count));
    std::atomic<bool> outside{false};
    tbb::parallel_for(
        tbb::blocked_range<int>(0, count, 32), [&](const tbb::blocked_range<int>& range) {
          for (int k = range.begin(); k != range.end(); ++k) {
            const Eigen::Vector3d x = basis_.position(k, controlPoints);
            if (!domain_.contains(x) || !x.allFinite()) {
              outside = true;
              return;
            }
            const Approximant approximant = target_.approximantAt(x);
            squared_[static_cast<std::size_t>(k)] = approximant.form(ErrorTerm::SDM)(x);
            measuredForms_[static_cast<std::size_t>(k)] = fitForm(approximant, method_, pdmWeight_);
          }
        });
    detail::DataError error;
    error.count = count;
    if (outside) {
      error.valid = false;
      measuredControlPoints_.clear();
      return error;
    }
    for (const double value : squared_) {  // fixed order: deterministic sum
      error.sum += value;
      error.maxSquared = std::max(error.maxSquared, value);
    }
    measuredControlPoints_ = controlPoints;
    return error;
  }

  void accept() override {
    acceptedControlPoints_.swap(measuredControlPoints_);
    acceptedForms_.swap(measuredForms_);
    acceptedFormsValid_ = !acceptedControlPoints_.empty();
  }

 private:
  const SquaredDistanceTarget& target_;
  Eigen::AlignedBox3d domain_;
  SensorBasis basis_;
  FitMethod method_;
  double pdmWeight_;
  // Sensor forms of the last measured and of the accepted net, with its control points (an
  // empty control-point list: none valid); linearize() hands the accepted forms over once.
  std::vector<Eigen::Vector3d> measuredControlPoints_, acceptedControlPoints_;
  std::vector<QuadraticForm> measuredForms_, acceptedForms_;
  bool acceptedFormsValid_ = false;
  std::vector<double> squared_;
};

// Messages show points with 6 significant digits.
std::string pointText(const Eigen::Vector3d& p) {
  return formatPoint(p, 6);
}

}  // namespace

CurveFitResult fitCurve(const BSplineCurve& initial, const SquaredDistanceTarget& target,
                        const CurveFitOptions& options) {
  detail::validateFitOptions(options);
  detail::requireNonDegenerate(initial, "the initial curve");
  TargetProblem problem(initial, target, options);
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
  // The one-sided distance (sensors to target) does not hold the ends of an open curve, which a
  // bending term would pull in along the target: automatic smoothing means none there.
  CurveFitOptions effective = options;
  if (effective.smoothness < 0.0 && !initial.isClosed()) effective.smoothness = 0.0;
  return detail::runCurveFit(initial, effective, problem);
}

}  // namespace d2vdb
