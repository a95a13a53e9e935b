// Level-set benchmarks:
//  - mesh to level set, in the same run: a direct openvdb::tools::meshToVolume call,
//    d2vdb::meshToLevelSet with exact signs (the default) and without them, so that the cost of
//    the wrapper and of the exact-sign pass show as ratios. Meshes: the bunny at resolutions 256
//    and 512, and two generated meshes of more than 800k triangles at resolution 512 (see
//    largeMesh());
//  - exact signs against OpenVDB's (unchecked) signs on scan-like meshes, both timed in each
//    iteration and reported as a ratio: a generated scan (scannedBunny()) and, when the
//    environment variable D2VDB_BENCH_SCAN names a mesh file, that file;
//  - .vdb write and read with and without Blosc.
// Every benchmark takes the thread count as its last argument (tbb::global_control).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <unordered_map>
#include <utility>
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

/// Splits every triangle into four at its edge midpoints (shared midpoints, so that the
/// connectivity of the input is kept: a closed mesh stays closed).
d2vdb::TriangleMesh subdivide(const d2vdb::TriangleMesh& mesh) {
  d2vdb::TriangleMesh result;
  result.positions = mesh.positions;
  result.triangles.reserve(4 * mesh.triangles.size());
  std::unordered_map<std::uint64_t, d2vdb::TriangleMesh::Index> midpoints;
  midpoints.reserve(2 * mesh.triangles.size());
  const auto midpoint = [&](d2vdb::TriangleMesh::Index a, d2vdb::TriangleMesh::Index b) {
    const std::uint64_t key = a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
    const auto [entry, inserted] = midpoints.try_emplace(
        key, static_cast<d2vdb::TriangleMesh::Index>(result.positions.size()));
    if (inserted) result.positions.push_back(0.5f * (mesh.positions[a] + mesh.positions[b]));
    return entry->second;
  };
  for (const auto& t : mesh.triangles) {
    const auto ab = midpoint(t[0], t[1]);
    const auto bc = midpoint(t[1], t[2]);
    const auto ca = midpoint(t[2], t[0]);
    result.triangles.push_back({t[0], ab, ca});
    result.triangles.push_back({t[1], bc, ab});
    result.triangles.push_back({t[2], ca, bc});
    result.triangles.push_back({ab, bc, ca});
  }
  return result;
}

/// A closed, non-convex, star-shaped mesh of 1,310,720 triangles: an icosahedron subdivided 8
/// times, its vertices projected to the unit sphere and pushed out radially to
/// r(n) = 1 + sum_k a_k cos(f_k n . d_k + phase_k) (six waves of frequencies 4 to 23 along fixed
/// directions, amplitudes summing to 0.6), which gives deep folds and ridges at many scales.
/// Radial displacement of a sphere by r > 0 cannot make the surface intersect itself.
d2vdb::TriangleMesh foldedSphere() {
  const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
  d2vdb::TriangleMesh mesh;
  mesh.positions = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                    {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < 8; ++level) {
    mesh = subdivide(mesh);
    for (Eigen::Vector3f& p : mesh.positions) p.normalize();
  }
  struct Wave {
    Eigen::Vector3d direction;
    double frequency, amplitude, phase;
  };
  const std::array<Wave, 6> waves{{{{1.0, 0.2, 0.1}, 4.0, 0.18, 0.3},
                                   {{-0.3, 1.0, 0.4}, 6.0, 0.14, 1.1},
                                   {{0.2, -0.5, 1.0}, 9.0, 0.11, 2.0},
                                   {{0.7, 0.7, -0.2}, 13.0, 0.08, 0.7},
                                   {{-0.6, 0.1, 0.8}, 17.0, 0.05, 2.6},
                                   {{0.3, -0.9, -0.3}, 23.0, 0.04, 1.7}}};
  for (Eigen::Vector3f& p : mesh.positions) {
    const Eigen::Vector3d n = p.cast<double>();
    double radius = 1.0;
    for (const Wave& wave : waves) {
      radius += wave.amplitude *
                std::cos(wave.frequency * n.dot(wave.direction.normalized()) + wave.phase);
    }
    p = (radius * n).cast<float>();
  }
  return mesh;
}

/// Meshes by benchmark argument: 0 the bunny, 1 the bunny subdivided 4 times (940,544
/// triangles, the same surface), 2 foldedSphere().
const d2vdb::TriangleMesh& meshFor(std::int64_t id) {
  if (id == 0) return bunny();
  if (id == 1) {
    static const d2vdb::TriangleMesh mesh = subdivide(subdivide(subdivide(subdivide(bunny()))));
    return mesh;
  }
  static const d2vdb::TriangleMesh mesh = foldedSphere();
  return mesh;
}

/// The bunny as a raw scan comes: four holes (the triangles within 4 % of the bounding box's
/// diagonal of four surface points removed), and eight junk flaps inside it (the triangles around
/// eight other surface points, copied, pushed inward by 3 % and kept open), two of them
/// pushed only halfway so that they cut the surface (self-intersection).
d2vdb::TriangleMesh scannedBunny() {
  const d2vdb::TriangleMesh& source = bunny();
  const d2vdb::BoundingBox box = d2vdb::boundingBox(source);
  const float diagonal = static_cast<float>(box.extent().norm());
  const Eigen::Vector3f center = (0.5 * (box.min + box.max)).cast<float>();
  const auto centroid = [&](const d2vdb::TriangleMesh::Triangle& t) {
    return Eigen::Vector3f(
        (source.positions[t[0]] + source.positions[t[1]] + source.positions[t[2]]) / 3.0f);
  };
  const std::size_t count = source.triangles.size();
  std::vector<Eigen::Vector3f> holes, flaps;
  for (std::size_t k = 0; k < 4; ++k)
    holes.push_back(centroid(source.triangles[(2 * k + 1) * count / 9]));
  for (std::size_t k = 0; k < 8; ++k)
    flaps.push_back(centroid(source.triangles[(2 * k + 1) * count / 17 + 7]));
  d2vdb::TriangleMesh mesh;
  mesh.positions = source.positions;
  for (const auto& t : source.triangles) {
    bool removed = false;
    for (const Eigen::Vector3f& h : holes)
      removed = removed || (centroid(t) - h).norm() < 0.04f * diagonal;
    if (!removed) mesh.triangles.push_back(t);
  }
  for (std::size_t k = 0; k < flaps.size(); ++k) {
    const float depth = (k < 2 ? 0.005f : 0.03f) * diagonal;
    for (const auto& t : source.triangles) {
      if ((centroid(t) - flaps[k]).norm() >= 0.03f * diagonal) continue;
      const auto base = static_cast<d2vdb::TriangleMesh::Index>(mesh.positions.size());
      for (const auto corner : t) {
        const Eigen::Vector3f p = source.positions[corner];
        mesh.positions.push_back(p + depth * (center - p).normalized());
      }
      mesh.triangles.push_back({base, base + 1, base + 2});
    }
  }
  return mesh;
}

double voxelSizeFor(const d2vdb::TriangleMesh& mesh, int resolution) {
  return mesh.triangles.empty() ? 1.0 : d2vdb::boundingBox(mesh).extent().maxCoeff() / resolution;
}

double voxelSizeFor(int resolution) {
  return voxelSizeFor(bunny(), resolution);
}

tbb::global_control threadLimit(const benchmark::State& state, int argument) {
  return tbb::global_control(tbb::global_control::max_allowed_parallelism,
                             static_cast<std::size_t>(state.range(argument)));
}

/// d2vdb::meshToLevelSet, with `exactSigns` as in LevelSetOptions.
void runD2vdb(benchmark::State& state, const d2vdb::TriangleMesh& mesh, double voxelSize,
              bool exactSigns) {
  d2vdb::LevelSetOptions options;
  options.voxelSize = voxelSize;
  options.halfWidth = 3.0;
  options.exactSigns = exactSigns;
  for (auto _ : state) {
    const d2vdb::LevelSetResult result = d2vdb::meshToLevelSet(mesh, options);
    benchmark::DoNotOptimize(result.grid->activeVoxelCount());
    state.counters["active_voxels"] = static_cast<double>(result.grid->activeVoxelCount());
    state.counters["corrected"] = static_cast<double>(result.signs.correctedVoxels);
    state.counters["winding_queries"] = static_cast<double>(result.signs.windingNumberQueries);
  }
}

/// A direct openvdb::tools::meshToVolume call (default flags, half-width 3).
void runOpenVdb(benchmark::State& state, const d2vdb::TriangleMesh& mesh, double voxelSize) {
  openvdb::initialize();
  const auto transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  // The conversion to OpenVDB's index-space input is part of what a direct caller must do too,
  // so it is timed.
  for (auto _ : state) {
    std::vector<openvdb::Vec3s> points;
    points.reserve(mesh.positions.size());
    for (const auto& p : mesh.positions) {
      points.push_back(transform->worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z())));
    }
    std::vector<openvdb::Vec3I> triangles;
    triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
    const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(
        points, triangles);
    const openvdb::FloatGrid::Ptr grid =
        openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *transform, 3.0f, 3.0f);
    benchmark::DoNotOptimize(grid->activeVoxelCount());
    state.counters["active_voxels"] = static_cast<double>(grid->activeVoxelCount());
  }
}

/// Arguments: {mesh (meshFor()), resolution, variant, threads}; variant 0 is a direct
/// openvdb::tools::meshToVolume call, 1 d2vdb::meshToLevelSet with exact signs (the default),
/// 2 the same without them.
void BM_MeshToLevelSet(benchmark::State& state) {
  const d2vdb::TriangleMesh& mesh = meshFor(state.range(0));
  const double voxelSize = voxelSizeFor(mesh, static_cast<int>(state.range(1)));
  const auto limit = threadLimit(state, 3);
  if (state.range(2) == 0) {
    runOpenVdb(state, mesh, voxelSize);
  } else {
    runD2vdb(state, mesh, voxelSize, state.range(2) == 1);
  }
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
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

// Arguments: {mesh, resolution, variant, threads} and {resolution, blosc, threads}. The three
// conversions of a case run one after the other, so that their ratios are measured side by side.
void meshToLevelSetCases(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"mesh", "res", "variant", "threads"});
  for (const int threads : {1, 2}) {
    for (const auto& [mesh, resolution] :
         std::array<std::pair<int, int>, 4>{{{0, 256}, {0, 512}, {1, 512}, {2, 512}}}) {
      for (const int variant : {0, 1, 2}) benchmark->Args({mesh, resolution, variant, threads});
    }
  }
}
// CPU time is that of the whole process (all threads): on a shared machine it is steadier than
// the wall-clock time.
BENCHMARK(BM_MeshToLevelSet)
    ->Apply(meshToLevelSetCases)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
/// Arguments: {mesh, resolution, threads}; mesh 0 is scannedBunny(), 1 the file that
/// D2VDB_BENCH_SCAN names (skipped without it). Each iteration converts with exact signs and
/// without them; counters: both times (s) and exact_over_openvdb, their ratio.
void BM_ExactSignsOnScans(benchmark::State& state) {
  static const d2vdb::TriangleMesh generated = scannedBunny();
  d2vdb::TriangleMesh file;
  if (state.range(0) == 1) {
    const char* path = std::getenv("D2VDB_BENCH_SCAN");
    if (path == nullptr) {
      state.SkipWithError("set D2VDB_BENCH_SCAN to a mesh file");
      return;
    }
    file = d2vdb::readMesh(path);
  }
  const d2vdb::TriangleMesh& mesh = state.range(0) == 0 ? generated : file;
  const auto limit = threadLimit(state, 2);
  d2vdb::LevelSetOptions options;
  options.voxelSize = voxelSizeFor(mesh, static_cast<int>(state.range(1)));
  double exactSeconds = 0.0, openVdbSeconds = 0.0;
  for (auto _ : state) {
    for (const bool exact : {false, true}) {
      options.exactSigns = exact;
      const auto start = std::chrono::steady_clock::now();
      const d2vdb::LevelSetResult result = d2vdb::meshToLevelSet(mesh, options);
      benchmark::DoNotOptimize(result.grid->activeVoxelCount());
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      (exact ? exactSeconds : openVdbSeconds) += seconds;
      if (exact) {
        state.counters["winding_queries"] = static_cast<double>(result.signs.windingNumberQueries);
        state.counters["self_intersecting"] = result.signs.selfIntersecting ? 1.0 : 0.0;
        state.counters["holes"] = static_cast<double>(result.signs.holesClosed);
      }
    }
  }
  const double iterations = static_cast<double>(state.iterations());
  state.counters["exact_s"] = exactSeconds / iterations;
  state.counters["openvdb_s"] = openVdbSeconds / iterations;
  state.counters["exact_over_openvdb"] = exactSeconds / openVdbSeconds;
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
}

BENCHMARK(BM_ExactSignsOnScans)
    ->ArgsProduct({{0, 1}, {256, 512}, {2}})
    ->ArgNames({"mesh", "res", "threads"})
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
