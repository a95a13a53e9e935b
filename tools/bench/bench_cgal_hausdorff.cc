// Certified mesh Hausdorff distance against CGAL 5.5, in the same run and at the same absolute
// error bound eps = 1e-6 of the diagonal of the bounding box of both meshes:
//  - BM_SymmetricHausdorff/workload: d2vdb::certifiedHausdorff on 1 and on 2 threads
//    (tbb::global_control) and CGAL::Polygon_mesh_processing::
//    bounded_error_symmetric_Hausdorff_distance (Sequential_tag, its only implementation),
//    alternately, kRepeats times each; counters: the medians d2vdb_t1_s, d2vdb_t2_s, cgal_s, the
//    ratio cgal_over_d2vdb (CGAL / d2vdb on 1 thread), speedup (1 thread / 2 threads), d2vdb's
//    bracket lower / upper, CGAL's value cgal and in_bracket (1 when lower - eps <= cgal <= upper
//    + eps, which both error bounds promise; a mismatch is also printed to stderr).
//  - BM_OneSidedHausdorff/workload/direction: the same for one direction (0: A -> B, 1: B -> A),
//    d2vdb::directedHausdorff against CGAL's bounded_error_Hausdorff_distance, 1 thread.
// Workloads (A, B): 0 the bundled bunny and a 10x decimation of it (CGAL's edge collapse to 10 %
// of the edges, Lindstrom-Turk); 1 the mesh file named by D2VDB_BENCH_DRAGON (the Stanford
// dragon) and a copy of it after kSmoothingSteps steps of uniform Laplacian smoothing (skipped
// without the variable); 2 a torus and a bumpy torus with different tessellations. Both sides see
// the same triangles: every mesh is a d2vdb::TriangleMesh (float positions) first, and CGAL's
// Surface_mesh gets those positions converted to double, as d2vdb's HausdorffShape does.
// Benchmark-only: CGAL is linked into this program and nothing else (tools/bench/CMakeLists.txt).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_ratio_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "BenchStatistics.h"
#include "d2vdb/measure/HausdorffShape.h"
#include "d2vdb/measure/MeshHausdorff.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

constexpr int kRepeats = 3;            // timings per side and workload; the medians are reported
constexpr double kRelativeEps = 1e-6;  // error bound, relative to the combined diagonal
constexpr int kSmoothingSteps = 3;     // uniform Laplacian steps of the dragon's smoothed copy

/// One workload: two meshes as both libraries see them.
struct MeshPair {
  std::string name;
  d2vdb::HausdorffShape a, b;
  CgalMesh cgalA, cgalB;
  double eps = 0.0;  // absolute error bound, world units
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The mesh without triangles that repeat a vertex index (points and segments that CGAL's
/// Surface_mesh cannot hold) and without vertices no triangle uses.
d2vdb::TriangleMesh cleaned(const d2vdb::TriangleMesh& mesh) {
  d2vdb::TriangleMesh result;
  std::vector<d2vdb::TriangleMesh::Index> newIndex(mesh.positions.size(), ~0u);
  for (const d2vdb::TriangleMesh::Triangle& triangle : mesh.triangles) {
    if (triangle[0] == triangle[1] || triangle[1] == triangle[2] || triangle[0] == triangle[2]) {
      continue;
    }
    d2vdb::TriangleMesh::Triangle mapped;
    for (int k = 0; k < 3; ++k) {
      d2vdb::TriangleMesh::Index& index = newIndex[triangle[k]];
      if (index == ~0u) {
        index = static_cast<d2vdb::TriangleMesh::Index>(result.positions.size());
        result.positions.push_back(mesh.positions[triangle[k]]);
      }
      mapped[k] = index;
    }
    result.triangles.push_back(mapped);
  }
  return result;
}

/// The mesh as a CGAL Surface_mesh with the same triangles: shared vertices where the halfedge
/// structure allows, a face of its own three vertices where it does not (non-manifold edges or
/// vertices, inconsistent orientation), so no triangle is lost.
CgalMesh toCgal(const d2vdb::TriangleMesh& mesh, std::size_t* detached = nullptr) {
  CgalMesh result;
  std::vector<CgalMesh::Vertex_index> vertices;
  vertices.reserve(mesh.positions.size());
  const auto point = [](const Eigen::Vector3f& p) {
    return Kernel::Point_3(double(p.x()), double(p.y()), double(p.z()));
  };
  for (const Eigen::Vector3f& p : mesh.positions) vertices.push_back(result.add_vertex(point(p)));
  std::size_t separate = 0;
  for (const d2vdb::TriangleMesh::Triangle& t : mesh.triangles) {
    if (result.add_face(vertices[t[0]], vertices[t[1]], vertices[t[2]]) != CgalMesh::null_face()) {
      continue;
    }
    ++separate;
    result.add_face(result.add_vertex(point(mesh.positions[t[0]])),
                    result.add_vertex(point(mesh.positions[t[1]])),
                    result.add_vertex(point(mesh.positions[t[2]])));
  }
  if (detached != nullptr) *detached = separate;
  return result;
}

/// A CGAL mesh (after edge collapse: with removed elements) as a d2vdb mesh, positions rounded
/// to float.
d2vdb::TriangleMesh fromCgal(const CgalMesh& mesh) {
  d2vdb::TriangleMesh result;
  std::map<CgalMesh::Vertex_index, d2vdb::TriangleMesh::Index> index;
  for (const CgalMesh::Vertex_index v : mesh.vertices()) {
    index[v] = static_cast<d2vdb::TriangleMesh::Index>(result.positions.size());
    const Kernel::Point_3& p = mesh.point(v);
    result.positions.emplace_back(float(p.x()), float(p.y()), float(p.z()));
  }
  for (const CgalMesh::Face_index f : mesh.faces()) {
    d2vdb::TriangleMesh::Triangle triangle;
    int k = 0;
    for (const CgalMesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      triangle[k++] = index.at(v);
    }
    result.triangles.push_back(triangle);
  }
  return result;
}

/// The mesh decimated by CGAL's edge collapse to `ratio` of its edges.
d2vdb::TriangleMesh decimated(const d2vdb::TriangleMesh& mesh, double ratio) {
  CgalMesh cgal = toCgal(mesh);
  const CGAL::Surface_mesh_simplification::Count_ratio_stop_predicate<CgalMesh> stop(ratio);
  CGAL::Surface_mesh_simplification::edge_collapse(cgal, stop);
  return fromCgal(cgal);
}

/// The mesh after `steps` steps of uniform Laplacian smoothing (each vertex moves halfway to the
/// mean of its edge neighbours).
d2vdb::TriangleMesh smoothed(const d2vdb::TriangleMesh& mesh, int steps) {
  std::vector<std::vector<d2vdb::TriangleMesh::Index>> neighbours(mesh.positions.size());
  for (const d2vdb::TriangleMesh::Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      neighbours[t[k]].push_back(t[(k + 1) % 3]);
      neighbours[t[k]].push_back(t[(k + 2) % 3]);
    }
  }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<Eigen::Vector3d> positions(mesh.positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i)
    positions[i] = mesh.positions[i].cast<double>();
  for (int step = 0; step < steps; ++step) {
    std::vector<Eigen::Vector3d> next = positions;
    for (std::size_t i = 0; i < positions.size(); ++i) {
      if (neighbours[i].empty()) continue;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto j : neighbours[i]) mean += positions[j];
      mean /= static_cast<double>(neighbours[i].size());
      next[i] = 0.5 * (positions[i] + mean);
    }
    positions.swap(next);
  }
  d2vdb::TriangleMesh result = mesh;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    result.positions[i] = positions[i].cast<float>();
  }
  return result;
}

/// A torus (axis z, radii 1 and 0.35) on an nu x nv grid, its tube radius changed by
/// `bump` * sin(5 u) sin(3 v) and the grid turned by `shift` cells in u.
d2vdb::TriangleMesh torus(int nu, int nv, double bump, double shift) {
  constexpr double kPi = 3.14159265358979323846;
  d2vdb::TriangleMesh mesh;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2.0 * kPi * (i + shift) / nu, v = 2.0 * kPi * j / nv;
      const double r = 0.35 + bump * std::sin(5.0 * u) * std::sin(3.0 * v);
      mesh.positions.emplace_back(float((1.0 + r * std::cos(v)) * std::cos(u)),
                                  float((1.0 + r * std::cos(v)) * std::sin(u)),
                                  float(r * std::sin(v)));
    }
  }
  const auto at = [&](int i, int j) {
    return static_cast<d2vdb::TriangleMesh::Index>((i % nu) * nv + j % nv);
  };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh;
}

/// Both sides' copies of two meshes, and the error bound.
MeshPair meshPair(std::string name, const d2vdb::TriangleMesh& a, const d2vdb::TriangleMesh& b) {
  MeshPair pair;
  pair.name = std::move(name);
  const d2vdb::TriangleMesh cleanA = cleaned(a), cleanB = cleaned(b);
  std::size_t detachedA = 0, detachedB = 0;
  pair.cgalA = toCgal(cleanA, &detachedA);
  pair.cgalB = toCgal(cleanB, &detachedB);
  pair.a = d2vdb::hausdorffShapeOfMesh(cleanA);
  pair.b = d2vdb::hausdorffShapeOfMesh(cleanB);
  pair.eps = kRelativeEps * d2vdb::combinedDiagonal(pair.a, pair.b);
  std::fprintf(stderr,
               "%s: A %zu triangles (%zu dropped as degenerate, %zu detached for CGAL), B %zu "
               "(%zu, %zu), eps %.6g\n",
               pair.name.c_str(), cleanA.triangles.size(),
               a.triangles.size() - cleanA.triangles.size(), detachedA, cleanB.triangles.size(),
               b.triangles.size() - cleanB.triangles.size(), detachedB, pair.eps);
  return pair;
}

/// The bunny and its 10x decimation.
const MeshPair& bunnyPair() {
  static const MeshPair pair = [] {
    const d2vdb::TriangleMesh mesh =
        d2vdb::readMesh(std::filesystem::path(D2VDB_SOURCE_DIR) / "volumes" / "bunny.obj");
    return meshPair("bunny / 10x decimated", mesh, decimated(mesh, 0.1));
  }();
  return pair;
}

/// The mesh D2VDB_BENCH_DRAGON names and its smoothed copy; nullptr without the variable.
const MeshPair* dragonPair() {
  static const std::unique_ptr<const MeshPair> pair = []() -> std::unique_ptr<const MeshPair> {
    const char* path = std::getenv("D2VDB_BENCH_DRAGON");
    if (path == nullptr) return nullptr;
    const d2vdb::TriangleMesh mesh = d2vdb::readMesh(path);
    return std::make_unique<const MeshPair>(
        meshPair(std::filesystem::path(path).filename().string() + " / smoothed", mesh,
                 smoothed(mesh, kSmoothingSteps)));
  }();
  return pair.get();
}

/// A torus (128k triangles) and a bumpy torus on another grid (108k triangles).
const MeshPair& torusPair() {
  static const MeshPair pair =
      meshPair("torus / bumpy torus", torus(400, 160, 0.0, 0.0), torus(360, 150, 0.01, 0.5));
  return pair;
}

/// The workload of benchmark argument `index`; nullptr when its input is missing.
const MeshPair* workload(int index) {
  switch (index) {
    case 0:
      return &bunnyPair();
    case 1:
      return dragonPair();
    default:
      return &torusPair();
  }
}

/// The workload of the state's first argument, or nullptr after skipping the benchmark.
const MeshPair* workloadOrSkip(benchmark::State& state) {
  const MeshPair* pair = workload(static_cast<int>(state.range(0)));
  if (pair == nullptr) {
    state.SkipWithError("set D2VDB_BENCH_DRAGON to a mesh file (the Stanford dragon)");
  }
  return pair;
}

/// Reports whether CGAL's value lies within eps of d2vdb's bracket, loudly when it does not.
bool checkAgreement(const MeshPair& pair, const char* what, double lower, double upper,
                    double cgal) {
  const bool inside = cgal >= lower - pair.eps && cgal <= upper + pair.eps;
  if (!inside) {
    std::fprintf(stderr,
                 "*** MISMATCH *** %s, %s: CGAL %.17g outside d2vdb's [%.17g, %.17g] +- eps "
                 "%.3g\n",
                 pair.name.c_str(), what, cgal, lower, upper, pair.eps);
  }
  return inside;
}

/// Prints every timing of one side to stderr, for the spread behind the medians.
void printTimes(const MeshPair& pair, const char* what, const std::vector<double>& seconds) {
  std::string line;
  for (const double s : seconds) line += " " + std::to_string(s);
  std::fprintf(stderr, "%s, %s: seconds%s\n", pair.name.c_str(), what, line.c_str());
}

/// Sets the counters both benchmarks share.
void setCounters(benchmark::State& state, const MeshPair& pair, double lower, double upper,
                 double cgal, bool inside, const std::vector<double>& t1,
                 const std::vector<double>& cgalSeconds) {
  state.counters["d2vdb_t1_s"] = d2vdb::bench::median(t1);
  state.counters["cgal_s"] = d2vdb::bench::median(cgalSeconds);
  state.counters["cgal_over_d2vdb"] = d2vdb::bench::median(cgalSeconds) / d2vdb::bench::median(t1);
  state.counters["lower"] = lower;
  state.counters["upper"] = upper;
  state.counters["cgal"] = cgal;
  state.counters["eps"] = pair.eps;
  state.counters["in_bracket"] = inside ? 1.0 : 0.0;
  state.counters["triangles_a"] = static_cast<double>(pair.a.triangles.size());
  state.counters["triangles_b"] = static_cast<double>(pair.b.triangles.size());
}

/// Arguments: the workload, and whether both directed brackets are refined to eps (1) or the
/// second only as far as H needs it (0, CertifiedHausdorffOptions::tightDirections, as CGAL's
/// symmetric call does). One benchmark iteration times each side kRepeats times, alternately;
/// the iteration time is d2vdb's on one thread (median).
void BM_SymmetricHausdorff(benchmark::State& state) {
  const MeshPair* pair = workloadOrSkip(state);
  if (pair == nullptr) return;
  d2vdb::CertifiedHausdorffOptions options;
  options.tolerance = pair->eps;
  options.relative = false;
  options.tightDirections = state.range(1) == 1;
  for (auto _ : state) {
    std::vector<double> t1, t2, cgalSeconds;
    d2vdb::CertifiedHausdorff result;
    double cgal = 0.0;
    bool converged = true;
    for (int repeat = 0; repeat < kRepeats; ++repeat) {
      for (const std::size_t threads : {std::size_t(1), std::size_t(2)}) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        const auto start = std::chrono::steady_clock::now();
        result = d2vdb::certifiedHausdorff(pair->a, pair->b, options);
        (threads == 1 ? t1 : t2).push_back(secondsSince(start));
        converged = converged && result.aToB.converged && result.bToA.converged;
      }
      const auto start = std::chrono::steady_clock::now();
      cgal = PMP::bounded_error_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
          pair->cgalA, pair->cgalB, pair->eps);
      cgalSeconds.push_back(secondsSince(start));
    }
    state.SetIterationTime(d2vdb::bench::median(t1));
    printTimes(*pair, "d2vdb 1 thread", t1);
    printTimes(*pair, "d2vdb 2 threads", t2);
    printTimes(*pair, "CGAL", cgalSeconds);
    const bool inside = checkAgreement(*pair, "symmetric", result.lower, result.upper, cgal);
    setCounters(state, *pair, result.lower, result.upper, cgal, inside, t1, cgalSeconds);
    state.counters["d2vdb_t2_s"] = d2vdb::bench::median(t2);
    state.counters["speedup"] = d2vdb::bench::median(t1) / d2vdb::bench::median(t2);
    state.counters["converged"] = converged ? 1.0 : 0.0;
    state.counters["refined"] =
        static_cast<double>(result.aToB.primitivesRefined + result.bToA.primitivesRefined);
    state.SetLabel(pair->name + (options.tightDirections ? "" : " (second direction loose)"));
  }
}

/// Arguments: the workload, the direction (0: h(A -> B), 1: h(B -> A)). d2vdb on one thread.
void BM_OneSidedHausdorff(benchmark::State& state) {
  const MeshPair* pair = workloadOrSkip(state);
  if (pair == nullptr) return;
  const bool aToB = state.range(1) == 0;
  const d2vdb::HausdorffShape& from = aToB ? pair->a : pair->b;
  const d2vdb::HausdorffShape& to = aToB ? pair->b : pair->a;
  const CgalMesh& cgalFrom = aToB ? pair->cgalA : pair->cgalB;
  const CgalMesh& cgalTo = aToB ? pair->cgalB : pair->cgalA;
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
  for (auto _ : state) {
    std::vector<double> t1, cgalSeconds;
    d2vdb::DirectedHausdorffBracket result;
    double cgal = 0.0;
    for (int repeat = 0; repeat < kRepeats; ++repeat) {
      auto start = std::chrono::steady_clock::now();
      result = d2vdb::directedHausdorff(from, to, pair->eps);
      t1.push_back(secondsSince(start));
      start = std::chrono::steady_clock::now();
      cgal =
          PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(cgalFrom, cgalTo, pair->eps);
      cgalSeconds.push_back(secondsSince(start));
    }
    state.SetIterationTime(d2vdb::bench::median(t1));
    printTimes(*pair, aToB ? "A -> B, d2vdb 1 thread" : "B -> A, d2vdb 1 thread", t1);
    printTimes(*pair, aToB ? "A -> B, CGAL" : "B -> A, CGAL", cgalSeconds);
    const bool inside =
        checkAgreement(*pair, aToB ? "h(A -> B)" : "h(B -> A)", result.lower, result.upper, cgal);
    setCounters(state, *pair, result.lower, result.upper, cgal, inside, t1, cgalSeconds);
    state.counters["converged"] = result.converged ? 1.0 : 0.0;
    state.counters["refined"] = static_cast<double>(result.primitivesRefined);
    state.SetLabel(pair->name + (aToB ? ", A -> B" : ", B -> A"));
  }
}

BENCHMARK(BM_SymmetricHausdorff)
    ->ArgsProduct({{0, 1, 2}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(1);
BENCHMARK(BM_OneSidedHausdorff)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
