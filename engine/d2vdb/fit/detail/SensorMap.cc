#include "d2vdb/fit/detail/SensorMap.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>

namespace d2vdb::detail {

SensorMap::SensorMap(int sensorCount, int order, int controlPointCount)
    : sensorCount_(sensorCount),
      order_(order),
      controlPointCount_(controlPointCount),
      indices_(static_cast<std::size_t>(sensorCount) * static_cast<std::size_t>(order)),
      weights_(indices_.size()) {}

void SensorMap::groupByKey(const std::vector<int>& keys) {
  const std::size_t count = keys.size();
  spanOrder_.assign(count, 0);
  spanBegin_.clear();
  if (count > 0) {
    const auto [lowest, highest] = std::minmax_element(keys.begin(), keys.end());
    const int first = *lowest;
    std::vector<int> start(static_cast<std::size_t>(*highest - first) + 2, 0);
    for (const int key : keys) ++start[static_cast<std::size_t>(key - first) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    for (std::size_t k = 0; k < count; ++k) {
      spanOrder_[static_cast<std::size_t>(start[static_cast<std::size_t>(keys[k] - first)]++)] =
          static_cast<int>(k);
    }
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (i == 0 || keys[static_cast<std::size_t>(spanOrder_[i])] !=
                      keys[static_cast<std::size_t>(spanOrder_[i - 1])]) {
      spanBegin_.push_back(static_cast<int>(i));
    }
  }
  spanBegin_.push_back(static_cast<int>(count));
}

std::vector<Eigen::Vector3d> SensorMap::positions(
    const std::vector<Eigen::Vector3d>& controlPoints) const {
  std::vector<Eigen::Vector3d> result(static_cast<std::size_t>(sensorCount_));
  tbb::parallel_for(tbb::blocked_range<int>(0, sensorCount_, 512),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int k = range.begin(); k != range.end(); ++k) {
                        result[static_cast<std::size_t>(k)] = position(k, controlPoints);
                      }
                    });
  return result;
}

}  // namespace d2vdb::detail
