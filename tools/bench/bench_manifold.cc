// Smooth surfaces from triangle meshes (parametric pseudo-manifolds): construction and evaluation
// speed, each benchmark taking the thread count as its last argument (tbb::global_control).
//  (a) construction of the Loop-based surface of the bunny (volumes/bunny.obj, 1839 vertices) and
//      of a dragon-sized mesh made reproducibly from it (the bunny after 4 Loop subdivision steps,
//      470k vertices); items = vertices;
//  (b) evaluation at random face points of the bunny's surface: position, position + normal,
//      position + curvatures; next to it, in the same run, the exact Loop limit surface (the
//      source) evaluated with first derivatives at the same points; items = points;
//  (c) the field of the bunny's smooth surface (`d2vdb field --smooth`: half-edge mesh, Loop
//      source, surface, every band voxel projected) next to the ordinary field of the same mesh
//      (`d2vdb field`: meshToLevelSet with exact signs, then the level-set estimator) at the same
//      voxel size, both built in every iteration; counters: seconds of each and their ratio
//      smooth / plain, wall clock and process CPU time (all threads).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <memory>
#include <random>
#include <vector>

#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/SmoothSurfaceField.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/LoopSubdivision.h"
#include "d2vdb/manifold/PseudoManifold.h"
#include "d2vdb/mesh/MeshIO.h"

namespace {

using d2vdb::HalfEdgeMesh;

tbb::global_control threadLimit(const benchmark::State& state, int argument) {
  return tbb::global_control(tbb::global_control::max_allowed_parallelism,
                             static_cast<std::size_t>(state.range(argument)));
}

const d2vdb::TriangleMesh& bunnyTriangles() {
  static const d2vdb::TriangleMesh mesh =
      d2vdb::readMesh(std::filesystem::path(D2VDB_SOURCE_DIR) / "volumes" / "bunny.obj");
  return mesh;
}

const std::shared_ptr<const HalfEdgeMesh>& bunny() {
  static const auto mesh = std::make_shared<const HalfEdgeMesh>(bunnyTriangles());
  return mesh;
}

/// The bunny after four Loop subdivision steps.
const std::shared_ptr<const HalfEdgeMesh>& dragonSized() {
  static const std::shared_ptr<const HalfEdgeMesh> mesh = [] {
    HalfEdgeMesh m = d2vdb::loopSubdivision(*bunny());
    for (int step = 1; step < 4; ++step) m = d2vdb::loopSubdivision(m);
    return std::make_shared<const HalfEdgeMesh>(std::move(m));
  }();
  return mesh;
}

const d2vdb::LoopLimitSurface& bunnyLoop() {
  static const d2vdb::LoopLimitSurface surface(bunny());
  return surface;
}

const d2vdb::PseudoManifold& bunnySurface() {
  static const d2vdb::PseudoManifold surface(bunnyLoop());
  return surface;
}

/// 200k random face points of the bunny (uniform barycentric coordinates).
const std::vector<d2vdb::FacePoint>& randomPoints() {
  static const std::vector<d2vdb::FacePoint> points = [] {
    std::mt19937 random(7);
    std::uniform_int_distribution<std::uint32_t> face(
        0, static_cast<std::uint32_t>(bunny()->faceCount() - 1));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<d2vdb::FacePoint> result;
    for (int i = 0; i < 200000; ++i) {
      double a = unit(random);
      double b = unit(random);
      if (a + b > 1.0) {
        a = 1.0 - a;
        b = 1.0 - b;
      }
      result.push_back({face(random), Eigen::Vector3d(1.0 - a - b, a, b)});
    }
    return result;
  }();
  return points;
}

void BM_BuildBunny(benchmark::State& state) {
  const auto limit = threadLimit(state, 0);
  const d2vdb::LoopLimitSurface& loop = bunnyLoop();
  for (auto _ : state) {
    const d2vdb::PseudoManifold surface(loop);
    benchmark::DoNotOptimize(surface.memoryBytes());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(bunny()->vertexCount()));
}
BENCHMARK(BM_BuildBunny)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BuildDragonSized(benchmark::State& state) {
  const auto limit = threadLimit(state, 0);
  const d2vdb::LoopLimitSurface loop(dragonSized());
  for (auto _ : state) {
    const d2vdb::PseudoManifold surface(loop);
    benchmark::DoNotOptimize(surface.memoryBytes());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(dragonSized()->vertexCount()));
  state.counters["vertices"] = static_cast<double>(dragonSized()->vertexCount());
}
BENCHMARK(BM_BuildDragonSized)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void evaluate(benchmark::State& state, d2vdb::Derivatives derivatives) {
  const auto limit = threadLimit(state, 0);
  const d2vdb::PseudoManifold& surface = bunnySurface();
  const auto& points = randomPoints();
  std::vector<d2vdb::SmoothPoint> results;
  for (auto _ : state) {
    surface.evaluate(points, derivatives, results);
    benchmark::DoNotOptimize(results.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(points.size()));
}

void BM_EvaluatePosition(benchmark::State& state) {
  evaluate(state, d2vdb::Derivatives::None);
}
void BM_EvaluatePositionNormal(benchmark::State& state) {
  evaluate(state, d2vdb::Derivatives::First);
}
void BM_EvaluateCurvature(benchmark::State& state) {
  evaluate(state, d2vdb::Derivatives::Second);
}

/// Chart derivatives of the second and of the third order (PseudoManifold::chartDerivatives and
/// chartThirdDerivatives, the projection's two kinds of evaluation) at the same random points,
/// in the chart of the nearest corner, one thread; counters: thread CPU seconds of each pass
/// and their ratio third / second.
void BM_ChartDerivativesThirdVsSecond(benchmark::State& state) {
  const d2vdb::PseudoManifold& surface = bunnySurface();
  const auto& points = randomPoints();
  std::vector<int> corners;
  for (const d2vdb::FacePoint& p : points) {
    int best = 0;
    for (int i = 1; i < 3; ++i) {
      if (p.bary[i] > p.bary[best]) best = i;
    }
    corners.push_back(best);
  }
  const auto threadSeconds = [] {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  };
  double second = 0.0, third = 0.0;
  for (auto _ : state) {
    double start = threadSeconds();
    for (std::size_t i = 0; i < points.size(); ++i) {
      benchmark::DoNotOptimize(surface.chartDerivatives(points[i], corners[i]).dd[2]);
    }
    second += threadSeconds() - start;
    start = threadSeconds();
    for (std::size_t i = 0; i < points.size(); ++i) {
      benchmark::DoNotOptimize(surface.chartThirdDerivatives(points[i], corners[i]).ddd[3]);
    }
    third += threadSeconds() - start;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(points.size()));
  state.counters["second_s"] = second / static_cast<double>(state.iterations());
  state.counters["third_s"] = third / static_cast<double>(state.iterations());
  state.counters["ratio"] = third / second;
}
BENCHMARK(BM_ChartDerivativesThirdVsSecond)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK(BM_EvaluatePosition)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EvaluatePositionNormal)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EvaluateCurvature)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Reference: the Loop limit surface with first derivatives at the same points.
void BM_LoopSourcePositionDerivatives(benchmark::State& state) {
  const auto limit = threadLimit(state, 0);
  const d2vdb::LoopLimitSurface& loop = bunnyLoop();
  const auto& points = randomPoints();
  std::vector<d2vdb::SourceJet> results(points.size());
  for (auto _ : state) {
    tbb::parallel_for(std::size_t{0}, points.size(),
                      [&](std::size_t i) { results[i] = loop.evaluate(points[i]); });
    benchmark::DoNotOptimize(results.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(points.size()));
}
BENCHMARK(BM_LoopSourcePositionDerivatives)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// Seconds of wall clock and of CPU time of the whole process (all threads).
struct Clocks {
  std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
  double cpu = processCpuSeconds();

  static double processCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
  double wallSince() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
  }
  double cpuSince() const { return processCpuSeconds() - cpu; }
};

/// `d2vdb field bunny.obj --smooth` against `d2vdb field bunny.obj` at the same voxel size
/// (longest side / resolution, half-width 3), both built from the triangle mesh in every
/// iteration, the ordinary field first. Arguments: resolution, threads.
void BM_FieldSmoothVsPlain(benchmark::State& state) {
  const auto limit = threadLimit(state, 1);
  const d2vdb::TriangleMesh& mesh = bunnyTriangles();
  Eigen::AlignedBox3d bounds;
  for (const Eigen::Vector3f& p : mesh.positions) bounds.extend(p.cast<double>());
  const double voxelSize = bounds.sizes().maxCoeff() / static_cast<double>(state.range(0));
  double plainWall = 0.0, plainCpu = 0.0, smoothWall = 0.0, smoothCpu = 0.0;
  std::uint64_t plainVoxels = 0, smoothVoxels = 0;
  for (auto _ : state) {
    {
      const Clocks clocks;
      d2vdb::LevelSetOptions options;
      options.voxelSize = voxelSize;
      options.halfWidth = 3.0;
      const d2vdb::LevelSetResult levelSet = d2vdb::meshToLevelSet(mesh, options);
      const auto field = d2vdb::ApproximantField::fromLevelSet(levelSet.grid);
      plainVoxels = field.statistics().levels.front().activeVoxels;
      plainWall += clocks.wallSince();
      plainCpu += clocks.cpuSince();
    }
    {
      const Clocks clocks;
      const auto halfEdges = std::make_shared<const HalfEdgeMesh>(mesh);
      const d2vdb::LoopLimitSurface loop(halfEdges);
      const d2vdb::PseudoManifold surface(loop);
      const auto field = d2vdb::smoothSurfaceField(surface, voxelSize, 3.0);
      smoothVoxels = field.statistics().levels.front().activeVoxels;
      smoothWall += clocks.wallSince();
      smoothCpu += clocks.cpuSince();
    }
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["plain_s"] = plainWall / n;
  state.counters["smooth_s"] = smoothWall / n;
  state.counters["ratio"] = smoothWall / plainWall;
  state.counters["plain_cpu_s"] = plainCpu / n;
  state.counters["smooth_cpu_s"] = smoothCpu / n;
  state.counters["cpu_ratio"] = smoothCpu / plainCpu;
  state.counters["plain_voxels"] = static_cast<double>(plainVoxels);
  state.counters["smooth_voxels"] = static_cast<double>(smoothVoxels);
}
BENCHMARK(BM_FieldSmoothVsPlain)
    ->Args({256, 1})
    ->Args({256, 2})
    ->Args({512, 2})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
