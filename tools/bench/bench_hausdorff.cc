// Curve Hausdorff benchmarks: d2vdb::hausdorffDistance on two cubic
// B-spline curves with 1, 10 and 100 knot spans, next to the brute-force reference (dense
// sampling plus golden-section refinement, tests/measure/BruteForceReference.h) run in the same
// process to the same 1e-9 accuracy. Arguments: spans, threads (tbb::global_control).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../../tests/measure/BruteForceReference.h"
#include "d2vdb/measure/CurveHausdorff.h"

namespace {

// Brute-force samples per knot span: the sparsest density at which the reference still finds
// every basin of these curves and agrees with d2vdb to 1e-9 (checked in every run, counter
// "relative_error").
constexpr int kBruteForceSamplesPerSpan = 16;

// Two wavy planar clamped cubics side by side, with `spans` knot spans each.
d2vdb::BSplineCurve wavyCurve(int spans, double phase, double amplitude, double offset) {
  std::vector<Eigen::Vector3d> points;
  const int count = spans + 3;
  for (int i = 0; i < count; ++i) {
    const double x = i + 0.37 * phase;
    points.emplace_back(
        x, amplitude * std::sin(1.7 * i + phase) + 0.3 * std::sin(0.45 * i) + offset, 0.0);
  }
  return d2vdb::BSplineCurve::clamped(3, points, 2);
}

struct CurvePair {
  d2vdb::BSplineCurve a;
  d2vdb::BSplineCurve b;
};

CurvePair curvePair(int spans) {
  return {wavyCurve(spans, 0.0, 1.0, 0.0), wavyCurve(spans, 1.0, 0.8, 0.6)};
}

tbb::global_control threadLimit(const benchmark::State& state) {
  return tbb::global_control(tbb::global_control::max_allowed_parallelism,
                             static_cast<std::size_t>(state.range(1)));
}

double bruteForceDistance(const CurvePair& pair) {
  return std::max(
      d2vdb::test::bruteForceHausdorff(pair.a, pair.b, kBruteForceSamplesPerSpan, true).value,
      d2vdb::test::bruteForceHausdorff(pair.b, pair.a, kBruteForceSamplesPerSpan, true).value);
}

void BM_Hausdorff_d2vdb(benchmark::State& state) {
  const auto limit = threadLimit(state);
  const CurvePair pair = curvePair(static_cast<int>(state.range(0)));
  d2vdb::HausdorffDistance result;
  for (auto _ : state) {
    result = d2vdb::hausdorffDistance(pair.a, pair.b);
    benchmark::DoNotOptimize(result.distance);
  }
  state.counters["distance"] = result.distance;
  state.counters["bracket_width"] = result.upperBound - result.lowerBound;
  state.counters["intervals"] =
      static_cast<double>(result.aToB.intervalsExamined + result.bToA.intervalsExamined);
}

void BM_Hausdorff_bruteForce(benchmark::State& state) {
  const auto limit = threadLimit(state);
  const CurvePair pair = curvePair(static_cast<int>(state.range(0)));
  double distance = 0.0;
  for (auto _ : state) {
    distance = bruteForceDistance(pair);
    benchmark::DoNotOptimize(distance);
  }
  const double exact = d2vdb::hausdorffDistance(pair.a, pair.b).distance;
  state.counters["distance"] = distance;
  state.counters["relative_error"] = std::abs(distance - exact) / exact;
}

void spansAndThreads(benchmark::internal::Benchmark* benchmark) {
  for (const int spans : {1, 10, 100}) {
    for (const int threads : {1, 2}) benchmark->Args({spans, threads});
  }
}

BENCHMARK(BM_Hausdorff_d2vdb)->Apply(spansAndThreads)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Hausdorff_bruteForce)
    ->Apply(spansAndThreads)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
