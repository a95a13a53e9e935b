// Support-function benchmarks (Gravesen, Juettler, Sir 2008; results in BENCHMARKS.md).
//  - BM_FitVsDenseProduct/samples/degree/threads: one least-squares fit (fitSupportFunction, no
//    report) next to the floor of a direct least-squares fit, one dense product M^T M of the same
//    3N x (L+1)^2 design matrix by Eigen (general product M.transpose() * M, and the symmetric
//    rank update that computes only half of it), timed alternately in every iteration. Counters:
//    fit_ms, mtm_ms, syrk_ms (medians) and the ratios fit/mtm, fit/syrk. Eigen's products run on
//    one thread (no OpenMP); `threads` limits TBB in the fit.
//  - BM_FitSpeedup/samples/degree: the fit with 1 and 2 threads alternately; counters t1_ms,
//    t2_ms (medians) and speedup.
//  - BM_Evaluate/degree/threads: SupportFunction::evaluate (x_h, radii, directions) at 1M random
//    normals; items per second.
//  - BM_FitAccuracy/degree: the fit to 12k exact random oriented samples of the ellipsoid (2, 1.5,
//    1); counters: max |x_h(n) - x(n)| / a and max |distance to the ellipsoid| / a over 100k random
//    normals, relative errors of the radii at e1 (c^2 / a and b^2 / a).
//  - BM_DualPolyhedron/subdivisions: the piecewise-linear support function of the ellipsoid on a
//    geodesic sphere; counters: folded edges (swallowtails) before and after the edge flips, flips,
//    Hausdorff distance of the dual polyhedron to the ellipsoid.
//  - BM_OffsetComparison/method/voxelsPerA/offsetIndex: the ellipsoid with semi-axes 2, 1.5, 1
//    offset by d = -0.3, 0.25, 1.0: method 0 = support function (fit at L = 24 from 12k exact
//    random oriented samples, tessellated over a geodesic sphere with about as many vertices as
//    the level-set mesh), method 1 = level set (meshToLevelSet of a 655k-vertex mesh of the
//    ellipsoid at voxel size a / voxelsPerA, OpenVDB's LevelSetFilter::offset, marching cubes).
//    Counters: error_max, error_rms (world units: | signed distance of each output vertex to the
//    ellipsoid - d |, exact point-ellipsoid distances), vertices, and the time split into setup
//    (fit / mesh to level set, paid once for any number of offsets, built once per voxel size)
//    and per-offset work (support: evaluating x_h + d n; level set: copy, offset, marching cubes).
#include <benchmark/benchmark.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <tbb/global_control.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include "BenchStatistics.h"
#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/support/PiecewiseLinearSupport.h"
#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/SupportFit.h"
#include "d2vdb/support/SupportTessellation.h"
#include "d2vdb/support/detail/SupportDesign.h"
#include "support/SupportTestSupport.h"

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

using d2vdb::bench::median;

using d2vdb::test::randomUnitVectors;

// The ellipsoid with semi-axes (2, 1.5, 1), centred at the origin (SupportTestSupport.h).
constexpr double kA = 2.0, kB = 1.5, kC = 1.0;
const d2vdb::test::Ellipsoid kEllipsoid{kA, kB, kC};

Eigen::Vector3d ellipsoidPoint(const Eigen::Vector3d& n) {
  return kEllipsoid.point(n);
}

d2vdb::OrientedSamples ellipsoidSamples(std::size_t count, unsigned seed) {
  return kEllipsoid.samples(count, seed);
}

double signedDistanceToEllipsoid(const Eigen::Vector3d& p) {
  return d2vdb::test::signedDistanceToEllipsoid(kEllipsoid, p);
}

void BM_FitVsDenseProduct(benchmark::State& state) {
  const auto samples = static_cast<std::size_t>(state.range(0));
  const int degree = static_cast<int>(state.range(1));
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(state.range(2)));
  const d2vdb::OrientedSamples data = ellipsoidSamples(samples, 1);
  const Eigen::MatrixXd design = d2vdb::detail::supportDesignMatrix(data.normals, degree);
  std::vector<double> fit, mtm, syrk;
  for (auto _ : state) {
    auto start = Clock::now();
    const d2vdb::SupportFunction h = d2vdb::fitSupportFunction(data, {degree});
    fit.push_back(secondsSince(start));
    benchmark::DoNotOptimize(h.coefficients().data());
    start = Clock::now();
    const Eigen::MatrixXd product = design.transpose() * design;
    mtm.push_back(secondsSince(start));
    benchmark::DoNotOptimize(product.data());
    start = Clock::now();
    Eigen::MatrixXd half = Eigen::MatrixXd::Zero(design.cols(), design.cols());
    half.selfadjointView<Eigen::Lower>().rankUpdate(design.transpose());
    syrk.push_back(secondsSince(start));
    benchmark::DoNotOptimize(half.data());
    state.SetIterationTime(fit.back());
  }
  state.counters["fit_ms"] = 1e3 * median(fit);
  state.counters["mtm_ms"] = 1e3 * median(mtm);
  state.counters["syrk_ms"] = 1e3 * median(syrk);
  state.counters["fit/mtm"] = median(fit) / median(mtm);
  state.counters["fit/syrk"] = median(fit) / median(syrk);
}

void BM_FitSpeedup(benchmark::State& state) {
  const auto samples = static_cast<std::size_t>(state.range(0));
  const int degree = static_cast<int>(state.range(1));
  const d2vdb::OrientedSamples data = ellipsoidSamples(samples, 2);
  std::vector<double> one, two;
  for (auto _ : state) {
    for (const int threads : {1, 2}) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(threads));
      const auto start = Clock::now();
      const d2vdb::SupportFunction h = d2vdb::fitSupportFunction(data, {degree});
      (threads == 1 ? one : two).push_back(secondsSince(start));
      benchmark::DoNotOptimize(h.coefficients().data());
    }
    state.SetIterationTime(one.back() + two.back());
  }
  d2vdb::bench::setSpeedupCounters(state, one, two);
}

void BM_Evaluate(benchmark::State& state) {
  const int degree = static_cast<int>(state.range(0));
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(state.range(1)));
  const d2vdb::SupportFunction h = d2vdb::fitSupportFunction(
      ellipsoidSamples(
          4 * static_cast<std::size_t>(degree + 1) * static_cast<std::size_t>(degree + 1), 3),
      {degree});
  const std::vector<Eigen::Vector3d> normals = randomUnitVectors(1000000, 4);
  for (auto _ : state) {
    const std::vector<d2vdb::SupportPoint> points = h.evaluate(normals);
    benchmark::DoNotOptimize(points.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(normals.size()));
}

// --- The offset comparison -----------------------------------------------------------------

constexpr double kOffsets[3] = {-0.3, 0.25, 1.0};

// Geodesic subdivision whose spacing on the ellipsoid (radii up to a^2 / c = 4, mean about 1.5)
// is about one voxel of a / voxelsPerA: 7, 8, 9 for 128, 256, 512.
int subdivisionsFor(int voxelsPerA) {
  const double voxel = kA / voxelsPerA;
  return d2vdb::geodesicSubdivisionsForSpacing(voxel / 1.5);
}

struct SupportSetup {
  d2vdb::SupportFunction h;
  double fitSeconds = 0.0;
};

const SupportSetup& supportSetup() {
  static const SupportSetup setup = [] {
    SupportSetup s;
    const d2vdb::OrientedSamples samples = ellipsoidSamples(12000, 23);
    const auto start = Clock::now();
    s.h = d2vdb::fitSupportFunction(samples, {24});
    s.fitSeconds = secondsSince(start);
    return s;
  }();
  return setup;
}

// The input of the level-set method: the ellipsoid as a mesh, a geodesic sphere of 655k vertices
// mapped to the exact surface points (chord sag at most r theta^2 / 8 = 1.1e-5).
const d2vdb::TriangleMesh& ellipsoidMesh() {
  static const d2vdb::TriangleMesh mesh = [] {
    const d2vdb::SphericalTriangulation sphere = d2vdb::geodesicSphere(8);
    d2vdb::TriangleMesh m;
    for (const auto& n : sphere.normals) {
      m.positions.push_back(ellipsoidPoint(n).cast<float>());
      m.normals.push_back(n.cast<float>());  // x_h(n) has the normal n
    }
    for (const auto& t : sphere.triangles) m.triangles.push_back({t[0], t[1], t[2]});
    return m;
  }();
  return mesh;
}

// The level set of the ellipsoid mesh at voxel size a / voxelsPerA, built once per size.
struct LevelSetSetup {
  openvdb::FloatGrid::Ptr grid;
  double seconds = 0.0;
};

const LevelSetSetup& levelSetSetup(int voxelsPerA) {
  static std::map<int, LevelSetSetup> cache;
  auto found = cache.find(voxelsPerA);
  if (found != cache.end()) return found->second;
  cache.clear();  // one level set in memory at a time
  d2vdb::LevelSetOptions options;
  options.voxelSize = kA / voxelsPerA;
  options.halfWidth = 3.0;
  const auto start = Clock::now();
  LevelSetSetup setup;
  setup.grid = d2vdb::meshToLevelSet(ellipsoidMesh(), options).grid;
  setup.seconds = secondsSince(start);
  return cache.emplace(voxelsPerA, std::move(setup)).first->second;
}

struct Errors {
  double max = 0.0;
  double rms = 0.0;
};

Errors offsetErrors(const std::vector<Eigen::Vector3d>& points, double d) {
  Errors e;
  double sum = 0.0;
  for (const auto& p : points) {
    const double error = std::abs(signedDistanceToEllipsoid(p) - d);
    e.max = std::max(e.max, error);
    sum += error * error;
  }
  e.rms = std::sqrt(sum / static_cast<double>(points.size()));
  return e;
}

void BM_OffsetComparison(benchmark::State& state) {
  const bool levelSet = state.range(0) == 1;
  const int voxelsPerA = static_cast<int>(state.range(1));
  const double d = kOffsets[state.range(2)];
  std::vector<Eigen::Vector3d> points;
  double setupSeconds = 0.0;
  std::vector<double> perOffset;
  for (auto _ : state) {
    if (!levelSet) {
      const SupportSetup& setup = supportSetup();
      setupSeconds = setup.fitSeconds;
      const d2vdb::SphericalTriangulation sphere =
          d2vdb::geodesicSphere(subdivisionsFor(voxelsPerA));
      const auto start = Clock::now();
      points = setup.h.points(sphere.normals, d);
      perOffset.push_back(secondsSince(start));
    } else {
      const LevelSetSetup& setup = levelSetSetup(voxelsPerA);
      setupSeconds = setup.seconds;
      const auto start = Clock::now();
      openvdb::FloatGrid::Ptr grid = setup.grid->deepCopy();
      openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*grid);
      filter.offset(static_cast<float>(-d));  // OpenVDB adds the value: + moves inward
      d2vdb::IsoSurfaceOptions iso;
      iso.computeNormals = false;
      const d2vdb::TriangleMesh mesh = d2vdb::extractIsoSurface(*grid, iso);
      perOffset.push_back(secondsSince(start));
      points.clear();
      for (const auto& p : mesh.positions) points.push_back(p.cast<double>());
    }
    state.SetIterationTime(perOffset.back());
  }
  const Errors errors = offsetErrors(points, d);
  state.counters["d"] = d;
  state.counters["error_max"] = errors.max;
  state.counters["error_rms"] = errors.rms;
  state.counters["vertices"] = static_cast<double>(points.size());
  state.counters["setup_s"] = setupSeconds;
  state.counters["offset_s"] = median(perOffset);
  state.counters["total_s"] = setupSeconds + median(perOffset);
}

// --- Accuracy of the fit and of the piecewise-linear duals --------------------------------------

void BM_FitAccuracy(benchmark::State& state) {
  const int degree = static_cast<int>(state.range(0));
  const d2vdb::OrientedSamples samples = ellipsoidSamples(12000, 23);
  d2vdb::SupportFunction h;
  for (auto _ : state) {
    h = d2vdb::fitSupportFunction(samples, {degree});
    benchmark::DoNotOptimize(h.coefficients().data());
  }
  const std::vector<Eigen::Vector3d> normals = randomUnitVectors(100000, 24);
  const std::vector<d2vdb::SupportPoint> points = h.evaluate(normals);
  double surface = 0.0;
  double distance = 0.0;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    surface = std::max(surface, (points[i].point - ellipsoidPoint(normals[i])).norm());
    distance = std::max(distance, std::abs(signedDistanceToEllipsoid(points[i].point)));
  }
  const d2vdb::SupportPoint tip = h.evaluate(Eigen::Vector3d::UnitX());
  state.counters["surface_error/a"] = surface / kA;
  state.counters["distance_error/a"] = distance / kA;
  state.counters["r1_rel_error"] = std::abs(tip.radius1 / (kC * kC / kA) - 1.0);
  state.counters["r2_rel_error"] = std::abs(tip.radius2 / (kB * kB / kA) - 1.0);
}

// Hausdorff distance between the dual polyhedron of the ellipsoid's support function sampled on a
// geodesic sphere and the ellipsoid (circumscribed polyhedron: the far side is at its vertices;
// an ellipsoid point's distance to the boundary is its distance to the nearest face plane).
void BM_DualPolyhedron(benchmark::State& state) {
  const int subdivisions = static_cast<int>(state.range(0));
  const auto support = [](const Eigen::Vector3d& n) { return kEllipsoid.support(n); };
  std::size_t foldedBefore = 0;
  std::size_t flips = 0;
  std::size_t foldedAfter = 0;
  double hausdorff = 0.0;
  for (auto _ : state) {
    d2vdb::PiecewiseLinearSupport pl =
        d2vdb::PiecewiseLinearSupport::sample(support, d2vdb::geodesicSphere(subdivisions));
    foldedBefore = pl.foldedEdges();
    flips = pl.removeSwallowtails();
    foldedAfter = pl.foldedEdges();
    hausdorff = 0.0;
    for (const Eigen::Vector3d& v : pl.dualVertices()) {
      hausdorff = std::max(hausdorff, signedDistanceToEllipsoid(v));
    }
    const auto& planes = pl.triangulation().normals;
    for (const Eigen::Vector3d& n : randomUnitVectors(2000, 5)) {
      const Eigen::Vector3d p = ellipsoidPoint(n);
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < planes.size(); ++i) {
        nearest = std::min(nearest, pl.values()[i] - planes[i].dot(p));
      }
      hausdorff = std::max(hausdorff, nearest);
    }
  }
  state.counters["hausdorff"] = hausdorff;
  state.counters["folded_before"] = static_cast<double>(foldedBefore);
  state.counters["flips"] = static_cast<double>(flips);
  state.counters["folded_after"] = static_cast<double>(foldedAfter);
}

}  // namespace

BENCHMARK(BM_FitAccuracy)->DenseRange(4, 28, 4)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_DualPolyhedron)->DenseRange(1, 5, 1)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_FitVsDenseProduct)
    ->Args({100000, 16, 1})
    ->Args({100000, 16, 2})
    ->Args({12000, 24, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);
BENCHMARK(BM_FitSpeedup)
    ->Args({100000, 16})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(7);
BENCHMARK(BM_Evaluate)
    ->Args({16, 1})
    ->Args({24, 1})
    ->Args({16, 2})
    ->Args({24, 2})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);

BENCHMARK(BM_OffsetComparison)
    ->Apply([](benchmark::internal::Benchmark* b) {
      // Grouped so that each level set is built once: method, then voxel size, then offset.
      for (const int method : {0, 1}) {
        for (const int voxels : {128, 256, 512}) {
          for (const int offset : {0, 1, 2}) b->Args({method, voxels, offset});
        }
      }
    })
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(1);

BENCHMARK_MAIN();
