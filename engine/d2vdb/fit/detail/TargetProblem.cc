// The fit loop's problem for a spline fitted to a SquaredDistanceTarget (detail/TargetProblem.h).
#include "d2vdb/fit/detail/TargetProblem.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb::detail {

TargetProblem::TargetProblem(const SquaredDistanceTarget& target,
                             std::unique_ptr<const SensorMap> sensors, FitMethod method,
                             double pdmWeight)
    : target_(target),
      domain_(target.domain()),
      sensors_(std::move(sensors)),
      method_(method),
      pdmWeight_(pdmWeight) {}

DataError TargetProblem::measure(const std::vector<Eigen::Vector3d>& controlPoints) {
  const int count = sensors_->sensorCount();
  measuredApproximants_.resize(static_cast<std::size_t>(count));
  squared_.resize(static_cast<std::size_t>(count));
  std::atomic<bool> outside{false};
  tbb::parallel_for(tbb::blocked_range<int>(0, count, 32),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int k = range.begin(); k != range.end(); ++k) {
                        const Eigen::Vector3d x = sensors_->position(k, controlPoints);
                        if (!domain_.contains(x) || !x.allFinite()) {
                          outside = true;
                          return;
                        }
                        const Approximant approximant = target_.approximantAt(x);
                        squared_[static_cast<std::size_t>(k)] = approximant.form(ErrorTerm::SDM)(x);
                        measuredApproximants_[static_cast<std::size_t>(k)] = approximant;
                      }
                    });
  DataError error;
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

void TargetProblem::accept() {
  acceptedControlPoints_.swap(measuredControlPoints_);
  acceptedApproximants_.swap(measuredApproximants_);
  acceptedValid_ = !acceptedControlPoints_.empty();
}

const std::vector<Approximant>& TargetProblem::approximantsAt(
    const std::vector<Eigen::Vector3d>& controlPoints) {
  // The loop linearises the net it last accepted, whose approximants measure() found.
  if (!(controlPoints == acceptedControlPoints_ && acceptedValid_)) {
    acceptedApproximants_ = target_.approximantsAt(sensors_->positions(controlPoints));
  }
  acceptedValid_ = false;
  return acceptedApproximants_;
}

void TargetProblem::setForms(const std::vector<Approximant>& approximants,
                             FitLinearization& linearization) const {
  linearization.basis = sensors_.get();
  std::vector<QuadraticForm>& forms = linearization.forms;
  forms.resize(approximants.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, approximants.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k != range.end(); ++k) {
                        forms[k] = fitForm(approximants[k], method_, pdmWeight_);
                      }
                    });
}

void TargetProblem::requireCovered(const std::vector<Eigen::Vector3d>& controlPoints,
                                   const std::string& spline) const {
  // Messages show points with 9 significant digits.
  const auto pointText = [](const Eigen::Vector3d& p) { return formatPoint(p, 9); };
  const std::vector<Eigen::Vector3d> positions = sensors_->positions(controlPoints);
  for (std::size_t k = 0; k < positions.size(); ++k) {
    if (domain_.contains(positions[k])) continue;
    const Eigen::Vector3d outside =
        (positions[k] - positions[k].cwiseMax(domain_.min()).cwiseMin(domain_.max())).cwiseAbs();
    throw InputError("the target (" + target_.describe() + ") does not cover the initial " +
                     spline + ": sensor " + std::to_string(k) + " at " + pointText(positions[k]) +
                     " lies " + std::to_string(outside.norm()) + " outside its working domain " +
                     pointText(domain_.min()) + " - " + pointText(domain_.max()) +
                     "; start from a " + spline +
                     " inside the domain or build the target with more padding");
  }
}

}  // namespace d2vdb::detail
