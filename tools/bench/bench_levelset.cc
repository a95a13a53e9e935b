// Level-set benchmarks:
//  - mesh to level set on the bunny at resolutions 256 and 512: d2vdb::meshToLevelSet next to a
//    direct openvdb::tools::meshToLevelSet call, so the wrapper's overhead shows as a ratio;
//  - .vdb write and read with and without Blosc.
// Every benchmark takes the thread count as its last argument (tbb::global_control).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <filesystem>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/MeshMeasures.h"

namespace {

const d2vdb::TriangleMesh& bunny() {
  static const d2vdb::TriangleMesh mesh =
      d2vdb::readMesh(std::filesystem::path(D2VDB_SOURCE_DIR) / "volumes" / "bunny.obj");
  return mesh;
}

double voxelSizeFor(int resolution) {
  return bunny().triangles.empty() ? 1.0
                                   : d2vdb::boundingBox(bunny()).extent().maxCoeff() / resolution;
}

tbb::global_control threadLimit(const benchmark::State& state, int argument) {
  return tbb::global_control(tbb::global_control::max_allowed_parallelism,
                             static_cast<std::size_t>(state.range(argument)));
}

void BM_MeshToLevelSet_d2vdb(benchmark::State& state) {
  const auto limit = threadLimit(state, 1);
  d2vdb::LevelSetOptions options;
  options.voxelSize = voxelSizeFor(static_cast<int>(state.range(0)));
  options.halfWidth = 3.0;
  for (auto _ : state) {
    const d2vdb::LevelSetResult result = d2vdb::meshToLevelSet(bunny(), options);
    benchmark::DoNotOptimize(result.grid->activeVoxelCount());
    state.counters["active_voxels"] = static_cast<double>(result.grid->activeVoxelCount());
  }
}

void BM_MeshToLevelSet_openvdb(benchmark::State& state) {
  const auto limit = threadLimit(state, 1);
  openvdb::initialize();
  const double voxelSize = voxelSizeFor(static_cast<int>(state.range(0)));
  const auto transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  // The conversion to OpenVDB's index-space input is part of what a direct caller must do too,
  // so it is timed.
  for (auto _ : state) {
    std::vector<openvdb::Vec3s> points;
    points.reserve(bunny().positions.size());
    for (const auto& p : bunny().positions) {
      points.push_back(transform->worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z())));
    }
    std::vector<openvdb::Vec3I> triangles;
    triangles.reserve(bunny().triangles.size());
    for (const auto& t : bunny().triangles) triangles.emplace_back(t[0], t[1], t[2]);
    const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(
        points, triangles);
    const openvdb::FloatGrid::Ptr grid =
        openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *transform, 3.0f, 3.0f);
    benchmark::DoNotOptimize(grid->activeVoxelCount());
    state.counters["active_voxels"] = static_cast<double>(grid->activeVoxelCount());
  }
}

openvdb::FloatGrid::Ptr bunnyLevelSet(int resolution) {
  d2vdb::LevelSetOptions options;
  options.voxelSize = voxelSizeFor(resolution);
  return d2vdb::meshToLevelSet(bunny(), options).grid;
}

std::filesystem::path scratchFile() {
  return std::filesystem::temp_directory_path() / "d2vdb-bench-levelset.vdb";
}

void BM_VdbWrite(benchmark::State& state) {
  const auto limit = threadLimit(state, 2);
  const openvdb::FloatGrid::Ptr grid = bunnyLevelSet(static_cast<int>(state.range(0)));
  d2vdb::VdbWriteOptions options;
  options.blosc = state.range(1) != 0;
  for (auto _ : state) d2vdb::writeVdb(scratchFile(), {grid}, options);
  state.counters["file_bytes"] = static_cast<double>(std::filesystem::file_size(scratchFile()));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * grid->memUsage()));
}

void BM_VdbRead(benchmark::State& state) {
  const auto limit = threadLimit(state, 2);
  const openvdb::FloatGrid::Ptr grid = bunnyLevelSet(static_cast<int>(state.range(0)));
  d2vdb::VdbWriteOptions options;
  options.blosc = state.range(1) != 0;
  d2vdb::writeVdb(scratchFile(), {grid}, options);
  for (auto _ : state) {
    const openvdb::FloatGrid::Ptr read = d2vdb::readLevelSet(scratchFile());
    benchmark::DoNotOptimize(read->activeVoxelCount());
  }
  state.counters["file_bytes"] = static_cast<double>(std::filesystem::file_size(scratchFile()));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * grid->memUsage()));
}

// Arguments: {resolution, threads} and {resolution, blosc, threads}.
BENCHMARK(BM_MeshToLevelSet_d2vdb)
    ->ArgsProduct({{256, 512}, {1, 2}})
    ->ArgNames({"res", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_MeshToLevelSet_openvdb)
    ->ArgsProduct({{256, 512}, {1, 2}})
    ->ArgNames({"res", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_VdbWrite)
    ->ArgsProduct({{256}, {0, 1}, {1, 2}})
    ->ArgNames({"res", "blosc", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_VdbRead)
    ->ArgsProduct({{256}, {0, 1}, {1, 2}})
    ->ArgNames({"res", "blosc", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
