// Curve fitting benchmarks.
//  - BM_FitIteration/sensors/controlPoints/threads: one fitting iteration (sensor queries,
//    assembly, solve, line-search evaluations) of a closed 2D cubic fitted to a 20000-vertex
//    polyline target, at 2k sensors / 100 control points and 20k / 1000; 1 and 2 threads
//    (tbb::global_control). Manual time: (fit of 6 iterations - fit of 1) / 5, so once-per-fit
//    work is not counted.
//  - BM_FitIterationSpeedup/sensors/controlPoints: the same iteration timed with 1 and 2 threads
//    alternately in every benchmark iteration (paired); counters t1_ms, t2_ms (medians), speedup.
//  - BM_CloudIteration/points/threads: one SDM II iteration on a noisy 3000-point cloud and on a
//    clean 20000-point sampling of a closed 2D curve (fixed bending weight, no early stop), timed
//    like BM_FitIteration.
//  - BM_Converge/case/method: a whole fit with default options (cap 1000) from the initial curve
//    `fit-curve` would use, on generated clouds of known curves: the closed three-lobed loop
//    (noisy and non-uniformly sampled 3:1, 3000 points, sigma 0.5 % of its size; clean, 20000
//    points; thick, uniform across a band of 2.5 % of its size), the open 3D helix (noisy, 3000
//    points); SDM, PDM, TDM+PDM and SDM without the exact second-order terms. Counters:
//    iterations, converged (1/0), rms_clean (RMS distance of the fit to the clean curve),
//    data_rms. The source builds against older versions of the library too (side-by-side runs).
//  - BM_SdmCorrection/case: SDM II with default options with and without the footpoint
//    correction (CurveFitOptions::footpointCorrection), run one after the other in each of three
//    benchmark iterations (paired), from the initial curve `fit-curve` would use: the open 2D wave
//    (t, 0.3 sin(1.25 pi t)) and the open 3D helix sampled cleanly (2000 points), the wavy closed
//    3D loop (r cos t, r sin t, 0.3 sin 3t), r = 1 + 0.25 cos 3t, noisy (3000 points), the closed
//    three-lobed loop clean (20000 points) and non-uniform noisy (3000). Counters: it_with,
//    it_without, ms_with, ms_without (medians), time_ratio (without / with), rms_with and
//    rms_without (to the clean curve), converged (both).
//  - BM_TimeToRms/<target>/<method>/<permille>: wall time for SDM and PDM, from the same initial
//    curve, to reach the same RMS error ((1 + permille / 1000) x the RMS SDM converges to with
//    default tolerances), on a noisy point cloud (SDM II) and on a curve field
//    (ApproximantField::fromCurve, SDM I). Counters: iterations, rms, reached (0 when the
//    3000-iteration cap came first).
//  - BM_SurfaceConverge/case/method: a whole surface fit with default options (cap 200): the
//    torus R = 2, r = 0.5 (its level set from primitiveLevelSet, voxel 0.01, through the
//    approximant field: SDM I), bicubic closed x closed, 16 x 16 and 8 x 8 control points, from a
//    torus of radii 1.7 and 0.8; a noisy cloud (SDM II) of z = 0.1 sin(3x) cos(2y) on [0, 2]^2,
//    sigma 0.002, 20000 points, 12 x 12 bicubic sheet. SDM, PDM, TDM+PDM. Counters: iterations,
//    converged, max_error and rms_error (to the analytic torus on 161 x 97 samples; for the cloud
//    the vertical RMS to the clean surface over [0.1, 1.9]^2), data_rms.
//  - BM_SurfaceTimeToRms/method: the 16 x 16 torus: wall time for SDM and PDM from the same start
//    to reach 1.02 x the RMS SDM converges to (cap 300 iterations; reached 0 when the cap came
//    first).
//  - BM_SurfaceNoisyCloud: SDM II on 100,000 points of z = 0.1 sin(3x) cos(2y) on [0, 2]^2 with
//    sigma 0.002 per coordinate, 12 x 12 bicubic, default options; and the same fit to the clean
//    points (the noise-free floor). Counters: iterations, converged, rms_clean (vertical RMS to
//    the clean surface over [0.1, 1.9]^2), floor (the clean fit's), bound = 1.15 sigma
//    sqrt(3mn/N) + floor (the goal: rms_clean <= bound).
//  - BM_SurfaceIteration/threads: one SDM I iteration on the torus field at 32 x 32 control points
//    and 102,400 sensors (manual time, as BM_FitIteration) and, in the same run, the field's batch
//    queries at its sensors: queries per iteration, query_ms, ratio = iteration / queries.
//  - BM_SurfaceIterationSpeedup: the same iteration with 1 and 2 threads, paired; t1_ms, t2_ms,
//    speedup.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "BenchStatistics.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/fit/CurveFitter.h"
#include "d2vdb/fit/InitialCurve.h"
#include "d2vdb/fit/InitialSurface.h"
#include "d2vdb/fit/PointCloudFitter.h"
#include "d2vdb/fit/SurfaceFitter.h"
#include "d2vdb/fit/detail/SurfaceSensorBasis.h"
#include "fit/FitTestSupport.h"

namespace {

constexpr double kTwoPi = 6.283185307179586476925;

// Options of the library version this file is built against (older versions have no
// moveTolerance or exactSecondOrder).
template <typename T, typename = void>
struct HasMoveTolerance : std::false_type {};
template <typename T>
struct HasMoveTolerance<T, std::void_t<decltype(std::declval<T&>().moveTolerance)>>
    : std::true_type {};
template <typename T, typename = void>
struct HasExactSecondOrder : std::false_type {};
template <typename T>
struct HasExactSecondOrder<T, std::void_t<decltype(std::declval<T&>().exactSecondOrder)>>
    : std::true_type {};

template <typename T, typename = void>
struct HasFootpointCorrection : std::false_type {};
template <typename T>
struct HasFootpointCorrection<T, std::void_t<decltype(std::declval<T&>().footpointCorrection)>>
    : std::true_type {};

/// Sets exactSecondOrder where the library has it; false when it has not and `use` is false
/// (plain SDM cannot be asked for separately there).
template <typename Options>
bool useExactSecondOrder(Options& options, bool use) {
  if constexpr (HasExactSecondOrder<Options>::value) {
    options.exactSecondOrder = use;
    return true;
  } else {
    (void)options;
    return use;
  }
}

/// Runs `fit` once per benchmark iteration and returns the last result (no result of the library
/// version's own layout is built by hand).
template <typename Fit>
auto lastResult(benchmark::State& state, Fit&& fit) {
  std::optional<decltype(fit())> result;
  for (auto _ : state) result.emplace(fit());
  return std::move(*result);
}

/// Every fit runs exactly maxIterations iterations.
template <typename Options>
void noEarlyStop(Options& options) {
  options.stepTolerance = 0.0;
  options.objectiveTolerance = 0.0;
  if constexpr (HasMoveTolerance<Options>::value) options.moveTolerance = 0.0;
}

// A closed flower-like curve r = 1 + 0.15 cos(7 theta), scaled by (1, 0.7).
Eigen::Vector3d flower(double theta) {
  const double r = 1.0 + 0.15 * std::cos(7.0 * theta);
  return {r * std::cos(theta), 0.7 * r * std::sin(theta), 0.0};
}

const d2vdb::CurveTarget& flowerTarget() {
  static const d2vdb::CurveTarget target = [] {
    d2vdb::Polyline polyline;
    for (int i = 0; i < 20000; ++i) polyline.points.push_back(flower(kTwoPi * i / 20000));
    polyline.closed = true;
    polyline.dimension = 2;
    return d2vdb::CurveTarget(polyline);
  }();
  return target;
}

/// The BM_FitIteration problem: a closed 2D cubic with `controlPoints` control points near the
/// flower, `sensors` sensors, a fixed bending weight and no early stop (every fit does exactly
/// the iterations asked for).
struct IterationProblem {
  IterationProblem(int sensors, int controlPoints) : initial(initialCurve(controlPoints)) {
    options.sensorsPerSpan = sensors / controlPoints;
    options.smoothness = 1e-8;
    noEarlyStop(options);
  }
  static d2vdb::BSplineCurve initialCurve(int controlPoints) {
    std::vector<Eigen::Vector3d> samples;
    for (int i = 0; i < 4 * controlPoints; ++i)
      samples.push_back(1.03 * flower(kTwoPi * i / (4 * controlPoints)));
    return d2vdb::fitPolylineLeastSquares(samples, true, 3, controlPoints, 2);
  }
  d2vdb::BSplineCurve initial;
  d2vdb::CurveFitOptions options;
};

constexpr int kTimedIterations = 5;

/// Seconds per iteration on the current thread limit: (a fit of 1 + kTimedIterations iterations
/// - a fit of 1) / kTimedIterations, so the once-per-fit work (smoothing matrix, initial
/// evaluation, checks) cancels out. `rms` gets the longer fit's final RMS distance. Returns a
/// negative value if a fit stopped early.
double secondsPerIteration(IterationProblem& problem, double& rms) {
  d2vdb::CurveFitOptions& options = problem.options;
  options.maxIterations = 1;
  const auto start = std::chrono::steady_clock::now();
  const d2vdb::CurveFitResult first = d2vdb::fitCurve(problem.initial, flowerTarget(), options);
  const auto middle = std::chrono::steady_clock::now();
  options.maxIterations = 1 + kTimedIterations;
  const d2vdb::CurveFitResult longer = d2vdb::fitCurve(problem.initial, flowerTarget(), options);
  const auto end = std::chrono::steady_clock::now();
  if (longer.iterations() != 1 + kTimedIterations || first.iterations() != 1) return -1.0;
  rms = longer.history.back().rmsDistance;
  // Not DoNotOptimize(rms): with GCC its "+m,r" constraint on a double handed back a wrong
  // value (6.27 instead of 0.0057), which the counter then reported.
  benchmark::DoNotOptimize(longer.history.data());
  const std::chrono::duration<double> once = middle - start, more = end - middle;
  return (more - once).count() / kTimedIterations;
}

/// A fit of one iteration outside any timing: TBB starts its worker threads on the first
/// parallel loop after a new global_control, a once-per-process cost that is not part of an
/// iteration.
void warmUp(IterationProblem& problem) {
  problem.options.maxIterations = 1;
  benchmark::DoNotOptimize(
      d2vdb::fitCurve(problem.initial, flowerTarget(), problem.options).history.data());
}

void BM_FitIteration(benchmark::State& state) {
  IterationProblem problem(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(state.range(2)));
  warmUp(problem);
  double rms = 0.0;
  for (auto _ : state) {
    const double seconds = secondsPerIteration(problem, rms);
    if (seconds < 0.0) {
      state.SkipWithError("a fit stopped early");
      break;
    }
    state.SetIterationTime(seconds);
  }
  state.counters["rms_after"] = rms;
}
BENCHMARK(BM_FitIteration)
    ->Args({2000, 100, 1})
    ->Args({2000, 100, 2})
    ->Args({20000, 1000, 1})
    ->Args({20000, 1000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

/// Paired measurement of the 2-thread speed-up: every benchmark iteration times one iteration
/// with 1 thread and right after it with 2, so slow drifts of this shared machine hit both
/// alike. Counters: medians of the 1- and 2-thread times (ms) and their ratio.
void BM_FitIterationSpeedup(benchmark::State& state) {
  IterationProblem problem(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  std::vector<double> times[2];
  double rms = 0.0;
  for (auto _ : state) {
    for (int threads = 1; threads <= 2; ++threads) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(threads));
      warmUp(problem);
      const double seconds = secondsPerIteration(problem, rms);
      if (seconds < 0.0) {
        state.SkipWithError("a fit stopped early");
        return;
      }
      times[threads - 1].push_back(seconds);
    }
  }
  d2vdb::bench::setSpeedupCounters(state, times[0], times[1]);
}
BENCHMARK(BM_FitIterationSpeedup)
    ->Args({2000, 100})
    ->Args({20000, 1000})
    ->Iterations(31)
    ->Unit(benchmark::kMillisecond);

// ---- Generated clouds of known curves (BM_CloudIteration, BM_Converge) ----

/// A known curve (FitTestSupport.h) with its dimension and size (the noise level's scale).
struct KnownCurve {
  d2vdb::test::ParametricCurve curve;
  int dimension;
  double size;
};

const KnownCurve kLobedLoop{d2vdb::test::threeLobedLoop(), 2, 2.4};
const KnownCurve kHelix{d2vdb::test::helixCurve(1.0, 0.25, 1.5), 3, 2.0};

const KnownCurve kOpenWave{d2vdb::test::openWave(), 2, 2.0};
const KnownCurve kWavyLoop{d2vdb::test::wavySpaceLoop(), 3, 2.5};

using d2vdb::test::Sampling;

/// `count` points of `known` sampled as d2vdb::test::generateCloud() does.
std::vector<Eigen::Vector3d> sampleCurve(const KnownCurve& known, Sampling sampling, int count,
                                         unsigned seed) {
  return d2vdb::test::generateCloud(known.curve, known.dimension, sampling, count, known.size, seed)
      .points;
}

/// The initial curve `fit-curve` would start from: an ellipse around the cloud (closed), a
/// least-squares curve through a rough ordered sketch of the curve (open).
d2vdb::BSplineCurve startingCurve(const KnownCurve& known,
                                  const std::vector<Eigen::Vector3d>& cloud, int controlPoints) {
  const d2vdb::test::ParametricCurve& curve = known.curve;
  if (curve.periodic) {
    return d2vdb::initialCurveAround(cloud, d2vdb::InitialShape::Ellipse, 3, controlPoints,
                                     known.dimension, 1.2);
  }
  std::vector<Eigen::Vector3d> sketch;
  for (int i = 0; i < 30; ++i) {
    sketch.push_back(curve.point(curve.start + (curve.end - curve.start) * i / 29.0) +
                     0.02 * known.size *
                         Eigen::Vector3d(std::sin(1.7 * i), std::cos(2.3 * i),
                                         known.dimension == 3 ? std::sin(0.7 * i) : 0.0));
  }
  return d2vdb::fitPolylineLeastSquares(sketch, false, 3, controlPoints, known.dimension);
}

/// Seconds per SDM II iteration (as secondsPerIteration()).
double secondsPerCloudIteration(const d2vdb::BSplineCurve& initial,
                                const std::vector<Eigen::Vector3d>& cloud) {
  d2vdb::CurveFitOptions options;
  options.smoothness = 1e-8;
  noEarlyStop(options);
  options.maxIterations = 1;
  const auto start = std::chrono::steady_clock::now();
  const d2vdb::CurveFitResult first = d2vdb::fitCurveToPoints(initial, cloud, options);
  const auto middle = std::chrono::steady_clock::now();
  options.maxIterations = 1 + kTimedIterations;
  const d2vdb::CurveFitResult longer = d2vdb::fitCurveToPoints(initial, cloud, options);
  const auto end = std::chrono::steady_clock::now();
  if (longer.iterations() != 1 + kTimedIterations || first.iterations() != 1) return -1.0;
  benchmark::DoNotOptimize(longer.history.data());
  const std::chrono::duration<double> once = middle - start, more = end - middle;
  return (more - once).count() / kTimedIterations;
}

void BM_CloudIteration(benchmark::State& state) {
  const bool clean = state.range(0) > 5000;
  const std::vector<Eigen::Vector3d> cloud =
      sampleCurve(kLobedLoop, clean ? Sampling::Clean : Sampling::NonUniform,
                  static_cast<int>(state.range(0)), 3);
  const d2vdb::BSplineCurve initial = startingCurve(kLobedLoop, cloud, 16);
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(state.range(1)));
  for (auto _ : state) {
    const double seconds = secondsPerCloudIteration(initial, cloud);
    if (seconds < 0.0) {
      state.SkipWithError("a fit stopped early");
      break;
    }
    state.SetIterationTime(seconds);
  }
}
BENCHMARK(BM_CloudIteration)
    ->Args({3000, 1})
    ->Args({3000, 2})
    ->Args({20000, 1})
    ->Args({20000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

void BM_Converge(benchmark::State& state) {
  struct Case {
    const char* name;
    const KnownCurve* curve;
    Sampling sampling;
    int points;
  };
  static const Case cases[] = {
      {"closed loop, non-uniform noisy, 3000 points", &kLobedLoop, Sampling::NonUniform, 3000},
      {"closed loop, clean, 20000 points", &kLobedLoop, Sampling::Clean, 20000},
      {"closed loop, thick, 3000 points", &kLobedLoop, Sampling::Thick, 3000},
      {"open 3D helix, noisy, 3000 points", &kHelix, Sampling::Noisy, 3000},
  };
  const Case& c = cases[state.range(0)];
  const int method = static_cast<int>(state.range(1));
  const std::vector<Eigen::Vector3d> cloud = sampleCurve(*c.curve, c.sampling, c.points, 17);
  const d2vdb::BSplineCurve initial = startingCurve(*c.curve, cloud, 16);
  d2vdb::CurveFitOptions options;
  options.maxIterations = 1000;
  options.method = method == 1   ? d2vdb::FitMethod::PDM
                   : method == 2 ? d2vdb::FitMethod::TDMPlusPDM
                                 : d2vdb::FitMethod::SDM;
  if (!useExactSecondOrder(options, method != 3)) {
    state.SkipWithError("this library has no exact second-order terms (SDM is plain here)");
    return;
  }
  const d2vdb::CurveFitResult result =
      lastResult(state, [&] { return d2vdb::fitCurveToPoints(initial, cloud, options); });
  state.counters["iterations"] = result.iterations();
  state.counters["converged"] = result.status == d2vdb::FitStatus::Converged ? 1.0 : 0.0;
  state.counters["rms_clean"] =
      d2vdb::test::splineToCurveInterior(result.curve, c.curve->curve, 1000);
  state.counters["data_rms"] = result.history.back().rmsDistance;
  static const char* methodNames[] = {"sdm", "pdm", "tdm+pdm", "sdm without second-order terms"};
  state.SetLabel(std::string(c.name) + ", " + methodNames[method]);
}
BENCHMARK(BM_Converge)
    ->ArgNames({"case", "method"})
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

void BM_SdmCorrection(benchmark::State& state) {
  struct Case {
    const char* name;
    const KnownCurve* curve;
    Sampling sampling;
    int points;
    int controlPoints;
  };
  static const Case cases[] = {
      {"open 2D wave, clean, 2000 points, 12 control points", &kOpenWave, Sampling::Clean, 2000,
       12},
      {"open 3D helix, clean, 2000 points, 16 control points", &kHelix, Sampling::Clean, 2000, 16},
      {"wavy closed 3D loop, noisy, 3000 points, 20 control points", &kWavyLoop, Sampling::Noisy,
       3000, 20},
      {"closed loop, clean, 20000 points, 16 control points", &kLobedLoop, Sampling::Clean, 20000,
       16},
      {"closed loop, non-uniform noisy, 3000 points, 16 control points", &kLobedLoop,
       Sampling::NonUniform, 3000, 16},
  };
  const Case& c = cases[state.range(0)];
  const std::vector<Eigen::Vector3d> cloud = sampleCurve(*c.curve, c.sampling, c.points, 17);
  const d2vdb::BSplineCurve initial = startingCurve(*c.curve, cloud, c.controlPoints);
  d2vdb::CurveFitOptions options;
  options.maxIterations = 1000;
  d2vdb::CurveFitOptions uncorrected = options;
  if constexpr (HasFootpointCorrection<d2vdb::CurveFitOptions>::value) {
    uncorrected.footpointCorrection = false;
  } else {
    state.SkipWithError("this library has no footpoint correction");
    return;
  }
  std::optional<d2vdb::CurveFitResult> with, without;
  std::vector<double> withSeconds, withoutSeconds;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    with.emplace(d2vdb::fitCurveToPoints(initial, cloud, options));
    const auto middle = std::chrono::steady_clock::now();
    without.emplace(d2vdb::fitCurveToPoints(initial, cloud, uncorrected));
    const auto end = std::chrono::steady_clock::now();
    const std::chrono::duration<double> first = middle - start, second = end - middle;
    withSeconds.push_back(first.count());
    withoutSeconds.push_back(second.count());
    state.SetIterationTime(first.count());
  }
  state.counters["it_with"] = with->iterations();
  state.counters["it_without"] = without->iterations();
  state.counters["converged"] =
      with->status == d2vdb::FitStatus::Converged && without->status == d2vdb::FitStatus::Converged
          ? 1.0
          : 0.0;
  using d2vdb::bench::median;
  state.counters["ms_with"] = 1e3 * median(withSeconds);
  state.counters["ms_without"] = 1e3 * median(withoutSeconds);
  state.counters["time_ratio"] = median(withoutSeconds) / median(withSeconds);
  state.counters["rms_with"] =
      d2vdb::test::splineToCurveInterior(with->curve, c.curve->curve, 1000);
  state.counters["rms_without"] =
      d2vdb::test::splineToCurveInterior(without->curve, c.curve->curve, 1000);
  state.SetLabel(c.name);
}
BENCHMARK(BM_SdmCorrection)
    ->ArgName("case")
    ->DenseRange(0, 4)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(3);

std::vector<Eigen::Vector3d> noisyFlowerCloud() {
  std::mt19937 engine(5);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::uniform_real_distribution<double> angle(0.0, kTwoPi);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 5000; ++i) {
    points.push_back(flower(angle(engine)) + Eigen::Vector3d(noise(engine), noise(engine), 0.0));
  }
  return points;
}

struct Problem {
  std::vector<Eigen::Vector3d> cloud;
  std::unique_ptr<d2vdb::ApproximantField> field;
  std::unique_ptr<d2vdb::BSplineCurve> initial;
  double cloudRms = 0.0;
  double fieldRms = 0.0;
};

const Problem& problem() {
  static const Problem instance = [] {
    Problem p;
    p.cloud = noisyFlowerCloud();
    p.field = std::make_unique<d2vdb::ApproximantField>(
        d2vdb::ApproximantField::fromCurve(flowerTarget(), 0.01, 8.0));
    p.initial = std::make_unique<d2vdb::BSplineCurve>(
        d2vdb::initialCurveAround(p.cloud, d2vdb::InitialShape::Ellipse, 3, 40, 2, 1.1));
    d2vdb::CurveFitOptions options;
    options.maxIterations = 300;  // default tolerances: SDM converges well before
    p.cloudRms = d2vdb::fitCurveToPoints(*p.initial, p.cloud, options).history.back().rmsDistance;
    p.fieldRms = d2vdb::fitCurve(*p.initial, *p.field, options).history.back().rmsDistance;
    return p;
  }();
  return instance;
}

void BM_TimeToRms(benchmark::State& state) {
  const bool cloud = state.range(0) == 0;
  const d2vdb::FitMethod method =
      state.range(1) == 0 ? d2vdb::FitMethod::SDM : d2vdb::FitMethod::PDM;
  const double factor = 1.0 + static_cast<double>(state.range(2)) * 1e-3;
  const Problem& p = problem();
  d2vdb::CurveFitOptions options;
  options.method = method;
  options.maxIterations = 3000;  // default tolerances otherwise: a fit may stop short (reached 0)
  options.distanceTolerance = factor * (cloud ? p.cloudRms : p.fieldRms);
  const d2vdb::CurveFitResult result = lastResult(state, [&] {
    return cloud ? d2vdb::fitCurveToPoints(*p.initial, p.cloud, options)
                 : d2vdb::fitCurve(*p.initial, *p.field, options);
  });
  state.counters["iterations"] = result.iterations();
  state.counters["rms"] = result.history.back().rmsDistance;
  state.counters["target_rms"] = options.distanceTolerance;
  state.counters["reached"] = result.history.back().rmsDistance <= options.distanceTolerance;
  state.SetLabel(std::string(cloud ? "point cloud" : "curve field") + ", " +
                 d2vdb::fitMethodName(method));
}
// Target RMS = (1 + permille / 1000) x the RMS SDM converges to: 2 %, 0.5 % and 0.1 % above it.
BENCHMARK(BM_TimeToRms)
    ->ArgNames({"cloud0_field1", "sdm0_pdm1", "permille"})
    ->ArgsProduct({{0, 1}, {0, 1}, {20, 5, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

// ---- Surfaces (BM_SurfaceConverge, BM_SurfaceTimeToRms) ----

const d2vdb::Torus& benchTorus() {
  static const d2vdb::Torus torus(Eigen::Vector3d::Zero(), 2.0, 0.5);
  return torus;
}

const d2vdb::ApproximantField& torusField() {
  static const d2vdb::ApproximantField field = [] {
    d2vdb::PrimitiveLevelSetOptions options;
    options.voxelSize = 0.01;
    options.halfWidth = 3;
    return d2vdb::ApproximantField::fromLevelSet(d2vdb::primitiveLevelSet(benchTorus(), options));
  }();
  return field;
}

d2vdb::BSplineSurface torusStart(int controlPoints) {
  return d2vdb::torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.7, 0.8,
                             d2vdb::SurfaceLayout{3, 3, controlPoints, controlPoints, true, true});
}

double waveHeight(double x, double y) {
  return 0.1 * std::sin(3 * x) * std::cos(2 * y);
}

/// `count` points of the wave z = waveHeight(x, y), uniform on [0, 2]^2, with Gaussian noise of
/// `sigma` per coordinate (random seed 4, as waveCloud()); sigma 0 = the clean points.
std::vector<Eigen::Vector3d> waveSamples(int count, double sigma) {
  std::mt19937 engine(4);
  std::uniform_real_distribution<double> unit(0.0, 2.0);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    const double x = unit(engine), y = unit(engine);
    const Eigen::Vector3d offset(noise(engine), noise(engine), noise(engine));
    points.push_back(Eigen::Vector3d(x, y, waveHeight(x, y)) + (sigma / 0.002) * offset);
  }
  return points;
}

const std::vector<Eigen::Vector3d>& waveCloud() {
  static const std::vector<Eigen::Vector3d> cloud = waveSamples(20000, 0.002);
  return cloud;
}

void surfaceErrors(benchmark::State& state, const d2vdb::BSplineSurface& surface, bool torus) {
  double largest = 0.0, sum = 0.0;
  int count = 0;
  for (const Eigen::Vector3d& p : surface.sample(161, 97)) {
    double d = 0.0;
    if (torus) {
      d = std::abs(benchTorus().signedDistance(p));
    } else {
      if (p.x() < 0.1 || p.x() > 1.9 || p.y() < 0.1 || p.y() > 1.9) continue;
      d = std::abs(p.z() - waveHeight(p.x(), p.y()));
    }
    largest = std::max(largest, d);
    sum += d * d;
    ++count;
  }
  state.counters["max_error"] = largest;
  state.counters["rms_error"] = std::sqrt(sum / std::max(count, 1));
}

void BM_SurfaceConverge(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const int method = static_cast<int>(state.range(1));
  static const char* caseNames[] = {"torus field 16 x 16", "torus field 8 x 8",
                                    "noisy cloud 20000 points, 12 x 12"};
  d2vdb::SurfaceFitOptions options;
  options.maxIterations = 200;
  options.method = method == 1   ? d2vdb::FitMethod::PDM
                   : method == 2 ? d2vdb::FitMethod::TDMPlusPDM
                                 : d2vdb::FitMethod::SDM;
  const bool torus = which < 2;
  if (torus) torusField();  // built once, outside the timing
  d2vdb::InitialSurfaceOptions placement;
  placement.layout = d2vdb::SurfaceLayout{3, 3, 12, 12, false, false};
  const d2vdb::BSplineSurface initial =
      torus ? torusStart(which == 0 ? 16 : 8) : d2vdb::initialSurfaceAround(waveCloud(), placement);
  const d2vdb::SurfaceFitResult result = lastResult(state, [&] {
    return torus ? d2vdb::fitSurface(initial, torusField(), options)
                 : d2vdb::fitSurfaceToPoints(initial, waveCloud(), options);
  });
  state.counters["iterations"] = result.iterations();
  state.counters["converged"] = result.status == d2vdb::FitStatus::Converged ? 1.0 : 0.0;
  state.counters["data_rms"] = result.history.back().rmsDistance;
  surfaceErrors(state, result.surface, torus);
  static const char* methodNames[] = {"sdm", "pdm", "tdm+pdm"};
  state.SetLabel(std::string(caseNames[which]) + ", " + methodNames[method]);
}
BENCHMARK(BM_SurfaceConverge)
    ->ArgNames({"case", "method"})
    ->ArgsProduct({{0, 1, 2}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

void BM_SurfaceTimeToRms(benchmark::State& state) {
  static const double sdmRms = [] {
    d2vdb::SurfaceFitOptions options;
    options.maxIterations = 200;
    return d2vdb::fitSurface(torusStart(16), torusField(), options).history.back().rmsDistance;
  }();
  d2vdb::SurfaceFitOptions options;
  options.method = state.range(0) == 0 ? d2vdb::FitMethod::SDM : d2vdb::FitMethod::PDM;
  options.maxIterations = 300;
  options.distanceTolerance = 1.02 * sdmRms;
  const d2vdb::BSplineSurface initial = torusStart(16);
  const d2vdb::SurfaceFitResult result =
      lastResult(state, [&] { return d2vdb::fitSurface(initial, torusField(), options); });
  state.counters["iterations"] = result.iterations();
  state.counters["rms"] = result.history.back().rmsDistance;
  state.counters["target_rms"] = options.distanceTolerance;
  state.counters["reached"] = result.history.back().rmsDistance <= options.distanceTolerance;
  state.SetLabel(std::string("torus field 16 x 16, ") + d2vdb::fitMethodName(options.method));
}
BENCHMARK(BM_SurfaceTimeToRms)
    ->ArgNames({"sdm0_pdm1"})
    ->DenseRange(0, 1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

/// Vertical RMS of the surface to the clean wave over [0.1, 1.9]^2 (61 x 61 samples).
double waveRms(const d2vdb::BSplineSurface& surface) {
  double sum = 0.0;
  int count = 0;
  for (const Eigen::Vector3d& p : surface.sample(61, 61)) {
    if (p.x() < 0.1 || p.x() > 1.9 || p.y() < 0.1 || p.y() > 1.9) continue;
    sum += std::pow(p.z() - waveHeight(p.x(), p.y()), 2);
    ++count;
  }
  return std::sqrt(sum / std::max(count, 1));
}

void BM_SurfaceNoisyCloud(benchmark::State& state) {
  constexpr int kPoints = 100000;
  constexpr double kSigma = 0.002;
  const std::vector<Eigen::Vector3d> noisy = waveSamples(kPoints, kSigma);
  const std::vector<Eigen::Vector3d> clean = waveSamples(kPoints, 0.0);
  d2vdb::InitialSurfaceOptions placement;
  placement.layout = d2vdb::SurfaceLayout{3, 3, 12, 12, false, false};
  const d2vdb::BSplineSurface initial = d2vdb::initialSurfaceAround(noisy, placement);
  const d2vdb::SurfaceFitResult result =
      lastResult(state, [&] { return d2vdb::fitSurfaceToPoints(initial, noisy, {}); });
  d2vdb::SurfaceFitOptions floorOptions;
  floorOptions.maxIterations = 30;
  const d2vdb::SurfaceFitResult floorFit =
      d2vdb::fitSurfaceToPoints(d2vdb::initialSurfaceAround(clean, placement), clean, floorOptions);
  const double floor = waveRms(floorFit.surface);
  state.counters["iterations"] = result.iterations();
  state.counters["converged"] = result.status == d2vdb::FitStatus::Converged ? 1.0 : 0.0;
  state.counters["rms_clean"] = waveRms(result.surface);
  state.counters["floor"] = floor;
  state.counters["floor_iterations"] = floorFit.iterations();
  state.counters["bound"] = 1.15 * kSigma * std::sqrt(3.0 * 12 * 12 / kPoints) + floor;
}
BENCHMARK(BM_SurfaceNoisyCloud)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// ---- One SDM I surface iteration against the field queries it makes (BM_SurfaceIteration*) ----

/// Forwards to a target and counts the approximant queries made through it (atomic, so the count
/// is exact for any thread count). Its resolvedLength() is 0, so that the fit's resolved-move floor
/// (1/100 of a voxel) does not end the timed fits early.
class CountingTarget final : public d2vdb::SquaredDistanceTarget {
 public:
  explicit CountingTarget(const d2vdb::SquaredDistanceTarget& target) : target_(target) {}
  d2vdb::TargetKind kind() const override { return target_.kind(); }
  Eigen::AlignedBox3d domain() const override { return target_.domain(); }
  d2vdb::Approximant approximantAt(const Eigen::Vector3d& point) const override {
    queries_.fetch_add(1, std::memory_order_relaxed);
    return target_.approximantAt(point);
  }
  std::vector<d2vdb::Approximant> approximantsAt(
      const std::vector<Eigen::Vector3d>& points) const override {
    queries_.fetch_add(static_cast<long long>(points.size()), std::memory_order_relaxed);
    return target_.approximantsAt(points);
  }
  std::string describe() const override { return target_.describe(); }
  long long queries() const { return queries_.load(); }

 private:
  const d2vdb::SquaredDistanceTarget& target_;
  mutable std::atomic<long long> queries_{0};
};

/// The speed case: the torus field (torusField()), a bicubic closed x closed net of
/// 32 x 32 control points from a torus of radii 1.7 and 0.8 (as the accuracy case), 10 x 10
/// sensors per knot cell (102,400 sensors), default options (automatic smoothing) without early
/// stop.
struct SurfaceIterationProblem {
  SurfaceIterationProblem() : initial(torusStart(32)) {
    options.sensorsPerSpan = 10;
    noEarlyStop(options);
  }
  d2vdb::BSplineSurface initial;
  d2vdb::SurfaceFitOptions options;
};

/// One surface iteration's time and queries, as secondsPerIteration() for curves: (a fit of
/// 1 + kTimedIterations iterations - a fit of 1) / kTimedIterations. `sensors` gets the sensor
/// positions of the longer fit's result (for timing the queries alone). Returns false if a fit
/// stopped early.
struct SurfaceIterationCost {
  double seconds = 0.0;
  double queries = 0.0;
  std::vector<Eigen::Vector3d> sensors;
};
bool surfaceIterationCost(SurfaceIterationProblem& problem, SurfaceIterationCost& cost) {
  const CountingTarget counting(torusField());
  d2vdb::SurfaceFitOptions& options = problem.options;
  options.maxIterations = 1;
  const auto start = std::chrono::steady_clock::now();
  const d2vdb::SurfaceFitResult first = d2vdb::fitSurface(problem.initial, counting, options);
  const auto middle = std::chrono::steady_clock::now();
  const long long firstQueries = counting.queries();
  options.maxIterations = 1 + kTimedIterations;
  const d2vdb::SurfaceFitResult longer = d2vdb::fitSurface(problem.initial, counting, options);
  const auto end = std::chrono::steady_clock::now();
  const long long longerQueries = counting.queries() - firstQueries;
  if (longer.iterations() != 1 + kTimedIterations || first.iterations() != 1) return false;
  const std::chrono::duration<double> once = middle - start, more = end - middle;
  cost.seconds = (more - once).count() / kTimedIterations;
  cost.queries = static_cast<double>(longerQueries - firstQueries) / kTimedIterations;
  const std::vector<Eigen::Vector2d> parameters =
      d2vdb::detail::uniformSurfaceSensorParameters(longer.surface, options.sensorsPerSpan);
  cost.sensors.clear();
  for (const Eigen::Vector2d& uv : parameters) {
    cost.sensors.push_back(longer.surface.evaluate(uv.x(), uv.y()));
  }
  return true;
}

/// Seconds per approximant query of the field at `points`: the batch query (approximantsAt, the
/// field's fastest path), median of 5.
double secondsPerQuery(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> times;
  for (int run = 0; run < 5; ++run) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<d2vdb::Approximant> answers = torusField().approximantsAt(points);
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    benchmark::DoNotOptimize(answers.data());
    times.push_back(elapsed.count() / static_cast<double>(points.size()));
  }
  return d2vdb::bench::median(times);
}

/// BM_SurfaceIteration/threads: one SDM I iteration of SurfaceIterationProblem (manual time) and,
/// in the same run, the field's batch queries at its sensors. Counters: queries (per iteration),
/// query_ms (the time of that many queries), iteration_ms (median), ratio = iteration time /
/// query time (median; the goal: at most 6 with one thread).
void BM_SurfaceIteration(benchmark::State& state) {
  torusField();  // built once, outside the timing
  SurfaceIterationProblem problem;
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(state.range(0)));
  SurfaceIterationCost cost;
  std::vector<double> ratios, queryTimes, iterationTimes;
  for (auto _ : state) {
    if (!surfaceIterationCost(problem, cost)) {
      state.SkipWithError("a fit stopped early");
      return;
    }
    const double queryTime = cost.queries * secondsPerQuery(cost.sensors);
    state.SetIterationTime(cost.seconds);
    ratios.push_back(cost.seconds / queryTime);
    queryTimes.push_back(queryTime);
    iterationTimes.push_back(cost.seconds);
  }
  // The median, beside the Time column's mean: one difference of two fits can be far off.
  state.counters["iteration_ms"] = 1e3 * d2vdb::bench::median(iterationTimes);
  state.counters["sensors"] = static_cast<double>(cost.sensors.size());
  state.counters["queries"] = cost.queries;
  state.counters["query_ms"] = 1e3 * d2vdb::bench::median(queryTimes);
  state.counters["ratio"] = d2vdb::bench::median(ratios);
}
BENCHMARK(BM_SurfaceIteration)
    ->ArgNames({"threads"})
    ->DenseRange(1, 2)
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

/// BM_SurfaceIterationSpeedup: the same iteration with 1 and right after it 2 threads in every
/// benchmark iteration (paired, as BM_FitIterationSpeedup); counters t1_ms, t2_ms (medians) and
/// speedup (the goal: at least 1.7).
void BM_SurfaceIterationSpeedup(benchmark::State& state) {
  torusField();
  SurfaceIterationProblem problem;
  std::vector<double> times[2];
  SurfaceIterationCost cost;
  for (auto _ : state) {
    for (int threads = 1; threads <= 2; ++threads) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(threads));
      if (!surfaceIterationCost(problem, cost)) {
        state.SkipWithError("a fit stopped early");
        return;
      }
      times[threads - 1].push_back(cost.seconds);
    }
  }
  d2vdb::bench::setSpeedupCounters(state, times[0], times[1]);
}
BENCHMARK(BM_SurfaceIterationSpeedup)->Iterations(3)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
