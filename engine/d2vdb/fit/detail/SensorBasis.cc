#include "d2vdb/fit/detail/SensorBasis.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb::detail {

SensorBasis::SensorBasis(const BSplineCurve& curve, std::vector<double> parameters)
    : SensorMap(static_cast<int>(parameters.size()), curve.degree() + 1, curve.controlPointCount()),
      parameters_(std::move(parameters)) {
  const KnotVector& knots = curve.knots();
  const ParameterInterval domain = curve.domain();
  const std::size_t count = parameters_.size();
  for (std::size_t k = 0; k < count; ++k) {
    if (!std::isfinite(parameters_[k])) {
      throw InputError("sensor parameter " + std::to_string(k) + " is not finite");
    }
    if (curve.isClosed()) parameters_[k] = domain.wrap(parameters_[k]);
  }
  std::vector<int> spans(count);
  const int p = curve.degree();
  // findSpan throws InputError for parameters outside an open curve's domain; checked serially
  // first so the error names the first offending sensor whatever the thread count.
  for (std::size_t k = 0; k < count; ++k) spans[k] = knots.findSpan(parameters_[k]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k != range.end(); ++k) {
                        const int span = spans[k];
                        const BasisValues values = basisValues(knots, span, parameters_[k]);
                        for (int j = 0; j <= p; ++j) {
                          const std::size_t slot =
                              k * static_cast<std::size_t>(order_) + static_cast<std::size_t>(j);
                          indices_[slot] = curve.controlPointIndex(span - p + j);
                          weights_[slot] = values[j];
                        }
                      }
                    });
  // Sensors grouped by span, in increasing span and, within a span, sensor order.
  groupByKey(spans);
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

}  // namespace d2vdb::detail
