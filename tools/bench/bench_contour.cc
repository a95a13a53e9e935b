// Marching-cubes benchmarks: d2vdb::extractIsoSurface next to
// openvdb::tools::volumeToMesh (adaptivity 0) on the same level sets in the same run: the bunny
// at resolution 512 and a sphere of radius 400 voxels, with 1 and 2 threads.
// Counters: active voxels, active voxels per second per thread, output sizes, and the peak heap
// memory of the call (bytes allocated through operator new above the level at the start,
// output included), measured by the counting operator new below.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <new>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/mesh/MeshIO.h"

// ---- heap accounting: every operator new carries its size in a 64-byte header ----------------
namespace {
std::atomic<std::int64_t> heapInUse{0};
std::atomic<std::int64_t> heapPeak{0};
constexpr std::size_t kHeader = 64;  // keeps every alignment up to 64 bytes

void* countedAllocate(std::size_t size, std::size_t alignment) {
  const std::size_t header = std::max(kHeader, alignment);
  void* raw = std::aligned_alloc(header, ((size + header + header - 1) / header) * header);
  if (!raw) throw std::bad_alloc();
  auto* base = static_cast<unsigned char*>(raw);
  reinterpret_cast<std::size_t*>(base + header)[-1] = size;
  reinterpret_cast<std::size_t*>(base + header)[-2] = header;
  const std::int64_t now = heapInUse.fetch_add(static_cast<std::int64_t>(size)) + size;
  std::int64_t peak = heapPeak.load();
  while (now > peak && !heapPeak.compare_exchange_weak(peak, now)) {
  }
  return base + header;
}

void countedFree(void* pointer) noexcept {
  if (!pointer) return;
  auto* user = static_cast<unsigned char*>(pointer);
  const std::size_t size = reinterpret_cast<std::size_t*>(user)[-1];
  const std::size_t header = reinterpret_cast<std::size_t*>(user)[-2];
  heapInUse.fetch_sub(static_cast<std::int64_t>(size));
  std::free(user - header);
}
}  // namespace

void* operator new(std::size_t size) {
  return countedAllocate(size, kHeader);
}
void* operator new[](std::size_t size) {
  return countedAllocate(size, kHeader);
}
void* operator new(std::size_t size, std::align_val_t align) {
  return countedAllocate(size, static_cast<std::size_t>(align));
}
void* operator new[](std::size_t size, std::align_val_t align) {
  return countedAllocate(size, static_cast<std::size_t>(align));
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return countedAllocate(size, kHeader);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return countedAllocate(size, kHeader);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* pointer) noexcept {
  countedFree(pointer);
}
void operator delete[](void* pointer) noexcept {
  countedFree(pointer);
}
void operator delete(void* pointer, std::size_t) noexcept {
  countedFree(pointer);
}
void operator delete[](void* pointer, std::size_t) noexcept {
  countedFree(pointer);
}
void operator delete(void* pointer, std::align_val_t) noexcept {
  countedFree(pointer);
}
void operator delete[](void* pointer, std::align_val_t) noexcept {
  countedFree(pointer);
}
void operator delete(void* pointer, std::size_t, std::align_val_t) noexcept {
  countedFree(pointer);
}
void operator delete[](void* pointer, std::size_t, std::align_val_t) noexcept {
  countedFree(pointer);
}
void operator delete(void* pointer, const std::nothrow_t&) noexcept {
  countedFree(pointer);
}
void operator delete[](void* pointer, const std::nothrow_t&) noexcept {
  countedFree(pointer);
}

namespace {

enum Shape : int { kBunny512 = 0, kSphere400 = 1 };

const openvdb::FloatGrid& levelSet(int shape) {
  static const openvdb::FloatGrid::Ptr bunny = [] {
    const d2vdb::TriangleMesh mesh =
        d2vdb::readMesh(std::filesystem::path(D2VDB_SOURCE_DIR) / "volumes" / "bunny.obj");
    d2vdb::LevelSetOptions options;
    options.resolution = 512;
    return d2vdb::meshToLevelSet(mesh, options).grid;
  }();
  static const openvdb::FloatGrid::Ptr sphere = [] {
    d2vdb::PrimitiveLevelSetOptions options;
    options.voxelSize = 1.0;
    options.maxActiveVoxels = std::uint64_t(1) << 32;
    return d2vdb::primitiveLevelSet(d2vdb::Sphere(Eigen::Vector3d(0.25, 0.5, 0.125), 400.0),
                                    options);
  }();
  return shape == kBunny512 ? *bunny : *sphere;
}

/// Runs `body` once per iteration under a thread limit and reports the common counters.
template <typename Body>
void measure(benchmark::State& state, const Body& body) {
  const openvdb::FloatGrid& grid = levelSet(static_cast<int>(state.range(0)));
  const auto threads = static_cast<std::size_t>(state.range(1));
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  std::int64_t peak = 0;
  for (auto _ : state) {
    const std::int64_t before = heapInUse.load();
    heapPeak.store(before);
    body(grid, state);
    peak = std::max(peak, heapPeak.load() - before);
  }
  const auto active = static_cast<double>(grid.activeVoxelCount());
  state.counters["active_voxels"] = active;
  state.counters["voxels_per_s_per_core"] = benchmark::Counter(
      active / static_cast<double>(threads), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["peak_MB"] = static_cast<double>(peak) / 1e6;
}

void BM_Contour_d2vdb(benchmark::State& state) {
  measure(state, [](const openvdb::FloatGrid& grid, benchmark::State& s) {
    d2vdb::IsoSurfaceOptions options;
    options.computeNormals = s.range(2) != 0;
    const d2vdb::TriangleMesh mesh = d2vdb::extractIsoSurface(grid, options);
    benchmark::DoNotOptimize(mesh.triangles.data());
    s.counters["vertices"] = static_cast<double>(mesh.vertexCount());
    s.counters["triangles"] = static_cast<double>(mesh.triangleCount());
  });
}

void BM_Contour_openvdb(benchmark::State& state) {
  measure(state, [](const openvdb::FloatGrid& grid, benchmark::State& s) {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(grid, points, triangles, quads, 0.0, 0.0);
    benchmark::DoNotOptimize(quads.data());
    s.counters["vertices"] = static_cast<double>(points.size());
    s.counters["triangles"] = static_cast<double>(triangles.size() + 2 * quads.size());
  });
}

// Arguments: {shape (0 = bunny 512, 1 = sphere r 400), threads, normals (ours only)}.
BENCHMARK(BM_Contour_d2vdb)
    ->ArgsProduct({{kBunny512, kSphere400}, {1, 2}, {1, 0}})
    ->ArgNames({"shape", "threads", "normals"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Contour_openvdb)
    ->ArgsProduct({{kBunny512, kSphere400}, {1, 2}})
    ->ArgNames({"shape", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
