// Approximant-field benchmarks, each next to its reference in the same run:
//  (a) building the field from the bunny level set at resolution 512, next to
//      openvdb::tools::meshToLevelSet making that level set;
//  (b) one approximant query next to one openvdb::tools::BoxSampler sample of the FloatGrid at
//      the same points, in random and in spatially coherent order;
//  (c) bytes per active voxel (counters of the build benchmark);
//  (d) 1 and 2 threads for the build and the batch query;
//  (e) the batch query of a field file at 1M points into a result file (io/QueryResultFile.h),
//      next to its parts measured in the same iteration: the in-process batch query (answerAll()
//      on the field just read) plus the files' I/O (reading the field and the points, writing
//      the answers already computed).
// Every benchmark takes the thread count as its last argument (tbb::global_control).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <random>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/FieldQuery.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/QueryResultFile.h"
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

/// The files of the batch benchmark, made once: the bunny field and 1M query points (800k in the
/// band, 200k uniform over the working domain, nearly all beyond the band), in a scratch folder.
struct BatchFiles {
  std::filesystem::path folder, field, points;
  std::size_t count = 0;
};

const BatchFiles& batchFiles() {
  static const BatchFiles files = [] {
    BatchFiles f;
    f.folder = std::filesystem::temp_directory_path() / "d2vdb-bench-batch-query";
    std::filesystem::create_directories(f.folder);
    f.field = f.folder / "bunny-field.vdb";
    f.points = f.folder / "points.xyz";
    d2vdb::writeField(f.field, bunnyField());
    std::vector<Eigen::Vector3d> points = bandPoints(true);
    points.resize(800000);
    std::mt19937 random(7);
    const Eigen::AlignedBox3d domain = bunnyField().domain();
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    while (points.size() < 1000000) {
      const Eigen::Vector3d t(unit(random), unit(random), unit(random));
      points.push_back(domain.min() + t.cwiseProduct(domain.sizes()));
    }
    d2vdb::writePointSet(f.points, points);
    f.count = points.size();
    return f;
  }();
  return files;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Argument 0: the result format (0 csv, 1 ply, 2 json); argument 1: threads. The iteration time
/// is the batch query's (what `d2vdb query FIELD --points P --out R` runs); counters give its
/// parts' reference and their ratio.
void BM_BatchQueryFile(benchmark::State& state) {
  const BatchFiles& files = batchFiles();
  const char* extensions[] = {".csv", ".ply", ".json"};
  const std::filesystem::path out =
      files.folder / (std::string("answers") + extensions[state.range(0)]);
  const auto limit = threadLimit(state, 1);
  double batch = 0.0, inProcess = 0.0, io = 0.0;
  std::uint64_t bytes = 0;
  for (auto _ : state) {
    // The reference: the files' I/O and the in-process batch query on the field just read (its
    // coarse levels are built by the first query beyond the band, as in the batch).
    auto start = std::chrono::steady_clock::now();
    const std::vector<Eigen::Vector3d> points = d2vdb::readPointSet(files.points);
    const d2vdb::ApproximantField field = d2vdb::readField(files.field);
    double ioSeconds = secondsSince(start);
    start = std::chrono::steady_clock::now();
    const std::vector<d2vdb::FieldAnswer> answers = d2vdb::answerAll(field, points);
    const double inProcessSeconds = secondsSince(start);
    start = std::chrono::steady_clock::now();
    d2vdb::writeQueryAnswers(out, field.kind(), answers, {});
    ioSeconds += secondsSince(start);
    // The batch query itself, from the files.
    start = std::chrono::steady_clock::now();
    {
      const std::vector<Eigen::Vector3d> batchPoints = d2vdb::readPointSet(files.points);
      const d2vdb::ApproximantField batchField = d2vdb::readField(files.field);
      d2vdb::writeFieldQueries(out, batchField, batchPoints, {});
    }
    const double batchSeconds = secondsSince(start);
    state.SetIterationTime(batchSeconds);
    batch += batchSeconds;
    inProcess += inProcessSeconds;
    io += ioSeconds;
    bytes = std::filesystem::file_size(out);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["batch_s"] = batch / n;
  state.counters["in_process_s"] = inProcess / n;
  state.counters["io_s"] = io / n;
  state.counters["ratio"] = batch / (inProcess + io);
  state.counters["points"] = static_cast<double>(files.count);
  state.counters["output_bytes"] = static_cast<double>(bytes);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * files.count));
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
BENCHMARK(BM_BatchQueryFile)
    ->ArgsProduct({{0, 1, 2}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(2);

BENCHMARK_MAIN();
