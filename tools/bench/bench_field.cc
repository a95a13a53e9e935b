// Approximant-field benchmarks, each next to its reference in the same run:
//  (a) building the field from the bunny level set at resolution 512, next to
//      openvdb::tools::meshToLevelSet making that level set;
//  (b) one approximant query next to one openvdb::tools::BoxSampler sample of the FloatGrid at
//      the same points, in random and in spatially coherent order;
//  (c) bytes per active voxel (counters of the build benchmark);
//  (d) 1 and 2 threads for the build and the batch query.
// Every benchmark takes the thread count as its last argument (tbb::global_control).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/MeshMeasures.h"

namespace {

const d2vdb::TriangleMesh& bunny() {
  static const d2vdb::TriangleMesh mesh =
      d2vdb::readMesh(std::filesystem::path(D2VDB_SOURCE_DIR) / "volumes" / "bunny.obj");
  return mesh;
}

tbb::global_control threadLimit(const benchmark::State& state, int argument) {
  return tbb::global_control(tbb::global_control::max_allowed_parallelism,
                             static_cast<std::size_t>(state.range(argument)));
}

/// openvdb::tools::meshToLevelSet of the bunny at `resolution` voxels along its longest side.
openvdb::FloatGrid::Ptr bunnyLevelSet(int resolution) {
  openvdb::initialize();
  const double voxelSize = d2vdb::boundingBox(bunny()).extent().maxCoeff() / resolution;
  const auto transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  // meshToLevelSet takes world-space points.
  std::vector<openvdb::Vec3s> points;
  points.reserve(bunny().positions.size());
  for (const auto& p : bunny().positions) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(bunny().triangles.size());
  for (const auto& t : bunny().triangles) triangles.emplace_back(t[0], t[1], t[2]);
  return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, 3.0f);
}

const openvdb::FloatGrid::Ptr& bunny512() {
  static const openvdb::FloatGrid::Ptr grid = bunnyLevelSet(512);
  return grid;
}

const d2vdb::ApproximantField& bunnyField() {
  static const d2vdb::ApproximantField field = d2vdb::ApproximantField::fromLevelSet(bunny512());
  return field;
}

/// Points in the band: active voxel centres with a random offset of up to half a voxel, in
/// coherent (tree) order or shuffled.
std::vector<Eigen::Vector3d> bandPoints(bool shuffled) {
  const auto& grid = *bunny512();
  std::mt19937 random(42);
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  std::vector<Eigen::Vector3d> points;
  std::size_t index = 0;
  for (auto voxel = grid.cbeginValueOn(); voxel; ++voxel, ++index) {
    if (index % 4 != 0) continue;  // a quarter of the band: about 875k points
    const openvdb::Coord c = voxel.getCoord();
    const openvdb::Vec3d w = grid.indexToWorld(
        openvdb::Vec3d(c.x() + jitter(random), c.y() + jitter(random), c.z() + jitter(random)));
    points.emplace_back(w.x(), w.y(), w.z());
  }
  if (shuffled) std::shuffle(points.begin(), points.end(), random);
  return points;
}

void BM_LevelSet_openvdb_meshToLevelSet(benchmark::State& state) {
  const auto limit = threadLimit(state, 0);
  for (auto _ : state) {
    const auto grid = bunnyLevelSet(512);
    benchmark::DoNotOptimize(grid->activeVoxelCount());
    state.counters["active_voxels"] = static_cast<double>(grid->activeVoxelCount());
  }
}

/// What construction does: the band's approximants (the coarse levels wait for the first query
/// beyond the band).
void BM_Field_fromLevelSet(benchmark::State& state) {
  const auto limit = threadLimit(state, 0);
  const auto grid = bunny512();
  for (auto _ : state) {
    const auto field = d2vdb::ApproximantField::fromLevelSet(grid);
    benchmark::DoNotOptimize(field.coarseLevelsBuilt());
    state.counters["active_voxels"] = static_cast<double>(grid->activeVoxelCount());
  }
}

/// Construction and the coarse levels: the whole structure, as the first query beyond the band
/// finds it.
void BM_Field_fromLevelSetWithCoarseLevels(benchmark::State& state) {
  const auto limit = threadLimit(state, 0);
  const auto grid = bunny512();
  for (auto _ : state) {
    const auto field = d2vdb::ApproximantField::fromLevelSet(grid);
    field.buildCoarseLevels();
    const d2vdb::FieldStatistics stats = field.statistics();
    const double active = static_cast<double>(stats.levels.front().activeVoxels);
    state.counters["active_voxels"] = active;
    state.counters["band_bytes_per_voxel"] =
        static_cast<double>(stats.levels.front().memoryBytes + stats.distanceGridBytes) / active;
    state.counters["total_bytes_per_voxel"] = static_cast<double>(stats.totalBytes) / active;
    state.counters["dense_over_total"] = stats.denseBytes / static_cast<double>(stats.totalBytes);
    state.counters["levels"] = field.levelCount();
  }
}

void BM_Query_field(benchmark::State& state, bool shuffled) {
  const auto& field = bunnyField();
  const auto points = bandPoints(shuffled);
  for (auto _ : state) {
    d2vdb::ApproximantField::Accessor accessor(field);
    double sum = 0.0;
    for (const auto& p : points) sum += accessor.approximantAt(p).distance;
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
}

void BM_Query_sdmForm(benchmark::State& state, bool shuffled) {
  const auto& field = bunnyField();
  const auto points = bandPoints(shuffled);
  for (auto _ : state) {
    d2vdb::ApproximantField::Accessor accessor(field);
    double sum = 0.0;
    for (const auto& p : points) {
      sum += accessor.approximantAt(p).form(d2vdb::ErrorTerm::SDM).c;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
}

void BM_Query_openvdb_BoxSampler(benchmark::State& state, bool shuffled) {
  const auto& grid = *bunny512();
  const auto points = bandPoints(shuffled);
  for (auto _ : state) {
    const auto accessor = grid.getConstAccessor();
    const openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler>
        sampler(accessor, grid.transform());
    double sum = 0.0;
    for (const auto& p : points) sum += sampler.wsSample(openvdb::Vec3d(p.x(), p.y(), p.z()));
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
}

void BM_BatchQuery(benchmark::State& state) {
  const auto& field = bunnyField();
  const auto points = bandPoints(true);
  const auto limit = threadLimit(state, 0);
  for (auto _ : state) {
    const auto answers = field.approximantsAt(points);
    benchmark::DoNotOptimize(answers.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
}

}  // namespace

BENCHMARK(BM_LevelSet_openvdb_meshToLevelSet)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Field_fromLevelSet)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Field_fromLevelSetWithCoarseLevels)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Query_field, random, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query_openvdb_BoxSampler, random, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query_sdmForm, random, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query_field, coherent, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query_openvdb_BoxSampler, coherent, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query_sdmForm, coherent, false)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BatchQuery)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
