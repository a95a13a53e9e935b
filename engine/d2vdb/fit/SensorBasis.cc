#include "d2vdb/fit/SensorBasis.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb {

SensorBasis::SensorBasis(const BSplineCurve& curve, std::vector<double> parameters)
    : parameters_(std::move(parameters)),
      order_(curve.degree() + 1),
      controlPointCount_(curve.controlPointCount()) {
  const KnotVector& knots = curve.knots();
  const ParameterInterval domain = curve.domain();
  const std::size_t count = parameters_.size();
  for (std::size_t k = 0; k < count; ++k) {
    if (!std::isfinite(parameters_[k])) {
      throw InputError("sensor parameter " + std::to_string(k) + " is not finite");
    }
    if (curve.isClosed()) parameters_[k] = domain.wrap(parameters_[k]);
  }
  indices_.resize(count * static_cast<std::size_t>(order_));
  weights_.resize(indices_.size());
  spans_.resize(count);
  const int p = curve.degree();
  // findSpan throws InputError for parameters outside an open curve's domain; checked serially
  // first so the error names the first offending sensor whatever the thread count.
  for (std::size_t k = 0; k < count; ++k) spans_[k] = knots.findSpan(parameters_[k]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k != range.end(); ++k) {
                        const int span = spans_[k];
                        const BasisValues values = basisValues(knots, span, parameters_[k]);
                        for (int j = 0; j <= p; ++j) {
                          const std::size_t slot =
                              k * static_cast<std::size_t>(order_) + static_cast<std::size_t>(j);
                          indices_[slot] = curve.controlPointIndex(span - p + j);
                          weights_[slot] = values[j];
                        }
                      }
                    });
  // Sensors grouped by span, in increasing span and, within a span, sensor order: a counting
  // sort (spans are knot indices, a small range).
  spanOrder_.resize(count);
  if (count > 0) {
    const auto [lowest, highest] = std::minmax_element(spans_.begin(), spans_.end());
    const int first = *lowest;
    std::vector<int> start(static_cast<std::size_t>(*highest - first) + 2, 0);
    for (const int span : spans_) ++start[static_cast<std::size_t>(span - first) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    for (std::size_t k = 0; k < count; ++k) {
      spanOrder_[static_cast<std::size_t>(start[static_cast<std::size_t>(spans_[k] - first)]++)] =
          static_cast<int>(k);
    }
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (i == 0 || spans_[static_cast<std::size_t>(spanOrder_[i])] !=
                      spans_[static_cast<std::size_t>(spanOrder_[i - 1])]) {
      spanBegin_.push_back(static_cast<int>(i));
    }
  }
  spanBegin_.push_back(static_cast<int>(count));
}

std::vector<Eigen::Vector3d> SensorBasis::positions(
    const std::vector<Eigen::Vector3d>& controlPoints) const {
  std::vector<Eigen::Vector3d> result(parameters_.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, sensorCount(), 512),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int k = range.begin(); k != range.end(); ++k) {
                        result[static_cast<std::size_t>(k)] = position(k, controlPoints);
                      }
                    });
  return result;
}

std::vector<double> uniformSensorParameters(const BSplineCurve& curve, int perSpan) {
  if (perSpan < 1) {
    throw InputError("sensors per knot span must be at least 1, got " + std::to_string(perSpan));
  }
  const std::vector<double> breaks = curve.knots().breakpoints();
  std::vector<double> parameters;
  parameters.reserve((breaks.size() - 1) * static_cast<std::size_t>(perSpan));
  for (std::size_t s = 0; s + 1 < breaks.size(); ++s) {
    const ParameterInterval span{breaks[s], breaks[s + 1]};
    if (s == 0 && !curve.isClosed()) parameters.push_back(span.start);
    for (int i = 0; i < perSpan; ++i) parameters.push_back(span.at((i + 0.5) / perSpan));
  }
  if (!curve.isClosed()) parameters.push_back(breaks.back());
  return parameters;
}

}  // namespace d2vdb
