#include "d2vdb/mesh/CurvatureColors.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/DistanceColors.h"

namespace d2vdb {
namespace {

std::array<double, 2> rangeOf(const std::vector<double>& values) {
  if (values.empty()) return {0.0, 0.0};
  const auto [low, high] = std::minmax_element(values.begin(), values.end());
  return {*low, *high};
}

}  // namespace

double nearestRankQuantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto index =
      static_cast<std::size_t>(std::clamp(std::ceil(q * static_cast<double>(values.size())) - 1.0,
                                          0.0, static_cast<double>(values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index),
                   values.end());
  return values[index];
}

CurvatureAttributes curvatureAttributes(const std::vector<double>& k1,
                                        const std::vector<double>& k2) {
  if (k1.size() != k2.size()) {
    throw InputError("curvature attributes: " + std::to_string(k1.size()) + " values of k1 but " +
                     std::to_string(k2.size()) + " of k2");
  }
  const std::size_t count = k1.size();
  CurvatureAttributes result;
  VertexAttributes& attributes = result.attributes;
  std::vector<float> k2Scalars(count);
  attributes.scalarName = "k1";
  attributes.scalars.resize(count);
  std::vector<double> mean(count), absMean(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(k1[i]) || !std::isfinite(k2[i])) {
      throw InputError("curvature attributes: vertex " + std::to_string(i) +
                       " has a non-finite curvature");
    }
    attributes.scalars[i] = static_cast<float>(k1[i]);
    k2Scalars[i] = static_cast<float>(k2[i]);
    mean[i] = 0.5 * (k1[i] + k2[i]);
    absMean[i] = std::abs(mean[i]);
  }
  CurvatureSummary& summary = result.summary;
  summary.colorScale = nearestRankQuantile(absMean, 0.99);
  attributes.colors.reserve(count);
  for (const double h : mean) attributes.colors.push_back(distanceColor(h, summary.colorScale));
  attributes.moreScalars.push_back({"k2", std::move(k2Scalars)});
  summary.k1Range = rangeOf(k1);
  summary.k2Range = rangeOf(k2);
  summary.meanRange = rangeOf(mean);
  summary.meanPercentiles = {nearestRankQuantile(mean, 0.01), nearestRankQuantile(mean, 0.5),
                             nearestRankQuantile(mean, 0.99)};
  return result;
}

}  // namespace d2vdb
