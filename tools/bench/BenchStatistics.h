// What the benchmarks report of repeated timings: medians, and paired two-thread speed-ups.
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

namespace d2vdb::bench {

/// The median of `values` (the upper middle one of an even count); `values` must not be empty.
inline double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

/// Counters t1_ms and t2_ms (the medians of the one- and two-thread times, given in seconds) and
/// speedup (the ratio of those medians).
inline void setSpeedupCounters(benchmark::State& state, const std::vector<double>& oneThread,
                               const std::vector<double>& twoThreads) {
  state.counters["t1_ms"] = 1e3 * median(oneThread);
  state.counters["t2_ms"] = 1e3 * median(twoThreads);
  state.counters["speedup"] = median(oneThread) / median(twoThreads);
}

}  // namespace d2vdb::bench
