#include "d2vdb/fit/detail/SurfaceSensorBasis.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb::detail {

SurfaceSensorBasis::SurfaceSensorBasis(const BSplineSurface& surface,
                                       std::vector<Eigen::Vector2d> parameters)
    : SensorMap(static_cast<int>(parameters.size()),
                (surface.degreeU() + 1) * (surface.degreeV() + 1),
                surface.countU() * surface.countV()),
      parameters_(std::move(parameters)) {
  const KnotVector& knotsU = surface.knotsU();
  const KnotVector& knotsV = surface.knotsV();
  const int p = surface.degreeU();
  const int q = surface.degreeV();
  const std::size_t count = parameters_.size();
  std::vector<int> spansU(count);
  std::vector<int> spansV(count);
  // Checked serially so that the error names the first offending sensor for any thread count.
  for (std::size_t k = 0; k < count; ++k) {
    Eigen::Vector2d& uv = parameters_[k];
    if (!uv.allFinite()) {
      throw InputError("surface sensor " + std::to_string(k) + " has a non-finite parameter");
    }
    if (surface.isClosedU()) uv.x() = surface.domainU().wrap(uv.x());
    if (surface.isClosedV()) uv.y() = surface.domainV().wrap(uv.y());
    spansU[k] = knotsU.findSpan(uv.x());
    spansV[k] = knotsV.findSpan(uv.y());
  }
  orderU_ = p + 1;
  uWeights_.resize(count * static_cast<std::size_t>(p + 1));
  vWeights_.resize(count * static_cast<std::size_t>(q + 1));
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, count, 256),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
          const BasisValues valuesU = basisValues(knotsU, spansU[k], parameters_[k].x());
          const BasisValues valuesV = basisValues(knotsV, spansV[k], parameters_[k].y());
          for (int a = 0; a <= p; ++a)
            uWeights_[k * static_cast<std::size_t>(p + 1) + a] = valuesU[a];
          for (int b = 0; b <= q; ++b)
            vWeights_[k * static_cast<std::size_t>(q + 1) + b] = valuesV[b];
          std::size_t slot = k * static_cast<std::size_t>(order_);
          for (int a = 0; a <= p; ++a) {
            for (int b = 0; b <= q; ++b, ++slot) {
              indices_[slot] = surface.controlPointIndex(spansU[k] - p + a, spansV[k] - q + b);
              weights_[slot] = valuesU[a] * valuesV[b];
            }
          }
        }
      });
  // Parameter keys: the rank of each sensor's u (v) among the distinct values.
  const auto keysOf = [&](int axis) {
    std::vector<double> distinct(count);
    for (std::size_t k = 0; k < count; ++k) distinct[k] = parameters_[k][axis];
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    std::vector<int> keys(count);
    for (std::size_t k = 0; k < count; ++k) {
      keys[k] = static_cast<int>(
          std::lower_bound(distinct.begin(), distinct.end(), parameters_[k][axis]) -
          distinct.begin());
    }
    return keys;
  };
  uKeys_ = keysOf(0);
  vKeys_ = keysOf(1);
  // One group per knot cell: key = (span u - p) * (spans in v) + (span v - q).
  const int spanCountV = knotsV.basisFunctionCount() - q;
  std::vector<int> keys(count);
  for (std::size_t k = 0; k < count; ++k) keys[k] = (spansU[k] - p) * spanCountV + spansV[k] - q;
  groupByKey(keys);
}

namespace {

std::vector<double> directionValues(const KnotVector& knots, bool closed, int perSpan) {
  const std::vector<double> breaks = knots.breakpoints();
  std::vector<double> values;
  if (!closed) values.push_back(breaks.front());
  for (std::size_t s = 0; s + 1 < breaks.size(); ++s) {
    const ParameterInterval span{breaks[s], breaks[s + 1]};
    for (int i = 0; i < perSpan; ++i) values.push_back(span.at((i + 0.5) / perSpan));
  }
  if (!closed) values.push_back(breaks.back());
  return values;
}

}  // namespace

std::vector<Eigen::Vector2d> uniformSurfaceSensorParameters(const BSplineSurface& surface,
                                                            int perSpan) {
  if (perSpan < 1) {
    throw InputError("sensors per knot span must be at least 1, got " + std::to_string(perSpan));
  }
  const std::vector<double> us = directionValues(surface.knotsU(), surface.isClosedU(), perSpan);
  const std::vector<double> vs = directionValues(surface.knotsV(), surface.isClosedV(), perSpan);
  std::vector<Eigen::Vector2d> parameters;
  parameters.reserve(us.size() * vs.size());
  for (const double u : us) {
    for (const double v : vs) parameters.emplace_back(u, v);
  }
  return parameters;
}

}  // namespace d2vdb::detail
