// Mesh to level set: accuracy against the analytic sphere, signs for damaged and open meshes,
// unsigned distance to a sheet, determinism, progress and refusals. The sign tests on meshes with
// sharp concave corners are in MeshToLevelSetSignsTest.cc.
#include "d2vdb/field/MeshToLevelSet.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "field/FieldTestSupport.h"
#include "field/WindingNumberReference.h"

namespace d2vdb {
namespace {

const Eigen::Vector3d kCenter(0.013, -0.021, 0.007);  // off the voxel lattice on purpose
constexpr double kRadius = 1.0;
constexpr double kVoxel = 0.05;  // the radius is 20 voxels

struct SphereComparison {
  double largestErrorNearSurface = 0.0;  // |grid - exact| over voxels with |d| < 1 voxel
  double largestErrorInBand = 0.0;       // over all active voxels
  std::size_t wrongSigns = 0;            // active voxels with 1.5 <= |d| voxels and wrong sign
  std::size_t checkedSigns = 0;
  std::size_t outsideBand = 0;  // active voxels with |value| >= band
};

SphereComparison compareWithSphere(const openvdb::FloatGrid& grid, double halfWidth) {
  const Sphere sphere(kCenter, kRadius);
  SphereComparison result;
  for (auto voxel = grid.cbeginValueOn(); voxel; ++voxel) {
    const openvdb::Vec3d world = grid.indexToWorld(voxel.getCoord());
    const double exact = sphere.signedDistance(Eigen::Vector3d(world.x(), world.y(), world.z()));
    const double error = std::abs(double(*voxel) - exact) / kVoxel;
    result.largestErrorInBand = std::max(result.largestErrorInBand, error);
    if (std::abs(exact) < kVoxel) {
      result.largestErrorNearSurface = std::max(result.largestErrorNearSurface, error);
    }
    if (std::abs(exact) >= 1.5 * kVoxel) {
      ++result.checkedSigns;
      if ((*voxel < 0.0f) != (exact < 0.0)) ++result.wrongSigns;
    }
    if (std::abs(*voxel) >= halfWidth * kVoxel) ++result.outsideBand;
  }
  return result;
}

TEST(MeshToLevelSet, TessellatedSphereMatchesAnalyticDistance) {
  const TriangleMesh mesh = test::makeIcosphere(kCenter, kRadius, 4);  // 5120 triangles
  // Vertices lie on the sphere and triangles inside it: the mesh is at most `chord` inside.
  const double chord = test::icosphereChordError(mesh, kCenter, kRadius) / kVoxel;
  ASSERT_LT(chord, 0.03);  // 0.023 voxels at this tessellation

  LevelSetOptions options;
  options.voxelSize = kVoxel;
  const LevelSetResult result = meshToLevelSet(mesh, options);
  ASSERT_TRUE(result.grid);
  EXPECT_TRUE(result.meshReport.closed);
  // A clean closed mesh gets no warning: voxels whose sign OpenVDB got wrong (here a few voxel
  // centres between the chords and the sphere) are corrected and counted in `signs` only.
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front();
  EXPECT_EQ(result.signs.method, SignMethod::closestFeature);
  EXPECT_TRUE(result.signs.watertight);
  EXPECT_FALSE(result.signs.selfIntersecting);
  EXPECT_EQ(result.signs.reorientedTriangles, 0u);
  EXPECT_EQ(result.signs.holesClosed, 0u);
  EXPECT_EQ(result.grid->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(result.grid->getName(), "surface");
  EXPECT_EQ(result.grid->metaValue<std::string>(kDistanceKindMetadata), "signed");
  EXPECT_EQ(result.grid->voxelSize(), openvdb::Vec3d(kVoxel));
  EXPECT_FLOAT_EQ(result.grid->background(), float(3 * kVoxel));

  // The brute-force checks below look at every fourth band voxel in the grid's order (a sample
  // spread over the whole band; all of them cost 5120 triangles each, too slow for the sanitizer
  // builds).
  constexpr std::size_t kSampleStride = 4;
  // Next to the surface (|value| < 1 voxel) OpenVDB computes the distance to the closest triangle
  // itself: check it against a brute-force distance to the mesh (float arithmetic in index space
  // allows ~1e-6 voxel).
  double largestMeshError = 0.0;
  std::size_t visited = 0;
  for (auto voxel = result.grid->cbeginValueOn(); voxel; ++voxel) {
    if (visited++ % kSampleStride != 0 || std::abs(*voxel) >= kVoxel) continue;
    const openvdb::Vec3d w = result.grid->indexToWorld(voxel.getCoord());
    const double exact = test::bruteForceMeshDistance(mesh, Eigen::Vector3d(w.x(), w.y(), w.z()));
    largestMeshError = std::max(largestMeshError, std::abs(std::abs(double(*voxel)) - exact));
  }
  EXPECT_LT(largestMeshError / kVoxel, 1e-4);

  // Against the analytic sphere: the mesh lies between the sphere and a surface `chord` inside
  // it, so the distances differ by at most the chord error near the surface. Further out OpenVDB
  // extends the band from neighbouring voxels' closest triangles and renormalises, which costs
  // up to ~0.11 voxel (measured 0.131 - 0.023 chord); 0.15 leaves a margin.
  // Every band voxel on the right side of the mesh itself: the icosphere is convex, so a point
  // is inside exactly when it is behind every face plane.
  std::size_t wrongSides = 0;
  visited = 0;
  for (auto voxel = result.grid->cbeginValueOn(); voxel; ++voxel) {
    if (visited++ % kSampleStride != 0 || std::abs(*voxel) < 1e-4 * kVoxel) continue;
    const openvdb::Vec3d w = result.grid->indexToWorld(voxel.getCoord());
    const Eigen::Vector3d p(w.x(), w.y(), w.z());
    bool inside = true;
    for (const TriangleMesh::Triangle& t : mesh.triangles) {
      const Eigen::Vector3d a = mesh.positions[t[0]].cast<double>();
      const Eigen::Vector3d n =
          (mesh.positions[t[1]].cast<double>() - a).cross(mesh.positions[t[2]].cast<double>() - a);
      if (n.dot(p - a) >= 0.0) {
        inside = false;
        break;
      }
    }
    if (inside != (*voxel < 0.0f)) ++wrongSides;
  }
  EXPECT_EQ(wrongSides, 0u);

  const SphereComparison comparison = compareWithSphere(*result.grid, 3.0);
  EXPECT_LT(comparison.largestErrorNearSurface, chord + 1e-3);
  EXPECT_LT(comparison.largestErrorInBand, chord + 0.15);
  EXPECT_GT(comparison.checkedSigns, 10000u);
  EXPECT_EQ(comparison.wrongSigns, 0u);
  EXPECT_EQ(comparison.outsideBand, 0u);
  // Every voxel within 2.5 voxels of the sphere is in the band.
  const Sphere sphere(kCenter, kRadius);
  const auto accessor = result.grid->getConstAccessor();
  std::size_t missing = 0;
  const int reach = static_cast<int>(std::ceil((kRadius + 3 * kVoxel) / kVoxel)) + 1;
  for (int i = -reach; i <= reach; ++i) {
    for (int j = -reach; j <= reach; ++j) {
      for (int k = -reach; k <= reach; ++k) {
        const double d = sphere.signedDistance(Eigen::Vector3d(i, j, k) * kVoxel);
        const bool active = accessor.isValueOn(openvdb::Coord(i, j, k));
        if (std::abs(d) < 2.5 * kVoxel && !active) ++missing;
        // Beyond the band the sign is still right (flood-filled tiles and inactive voxels).
        if (!active && std::abs(d) > 3.5 * kVoxel) {
          EXPECT_EQ(accessor.getValue(openvdb::Coord(i, j, k)) < 0.0f, d < 0.0);
        }
      }
    }
  }
  EXPECT_EQ(missing, 0u);
}

TEST(MeshToLevelSet, ResolutionSetsTheVoxelSize) {
  const TriangleMesh mesh = test::makeIcosphere(kCenter, kRadius, 2);
  LevelSetOptions options;
  options.resolution = 40;
  const LevelSetResult result = meshToLevelSet(mesh, options);
  const double longest = [&] {
    Eigen::Vector3f lo = mesh.positions[0];
    Eigen::Vector3f hi = mesh.positions[0];
    for (const Eigen::Vector3f& p : mesh.positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    return double((hi - lo).maxCoeff());
  }();
  EXPECT_NEAR(result.grid->voxelSize()[0], longest / 40.0, 1e-12);
}

TEST(MeshToLevelSet, DamagedSphereStillSignedCorrectlyWithWarning) {
  TriangleMesh mesh = test::makeIcosphere(kCenter, kRadius, 4);
  // Flip six triangles and remove five others, spread over the sphere. Each hole is one
  // triangle, about 1.4 voxels across.
  for (const std::size_t index : {17u, 900u, 1801u, 2702u, 3603u, 4504u}) {
    std::swap(mesh.triangles[index][1], mesh.triangles[index][2]);
  }
  for (const std::size_t index : {4800u, 3300u, 2500u, 1200u, 300u}) {
    mesh.triangles.erase(mesh.triangles.begin() + static_cast<std::ptrdiff_t>(index));
  }
  LevelSetOptions options;
  options.voxelSize = kVoxel;
  const LevelSetResult result = meshToLevelSet(mesh, options);
  EXPECT_FALSE(result.meshReport.closed);
  EXPECT_TRUE(test::containsText(result.warnings, "not closed"));
  EXPECT_TRUE(test::containsText(result.warnings, "6 of 5115 triangles were wound against"));
  EXPECT_EQ(result.signs.reorientedTriangles, 6u);
  EXPECT_EQ(result.signs.holesClosed, 5u);
  EXPECT_FALSE(result.signs.watertight);
  EXPECT_EQ(result.signs.method, SignMethod::closestFeature);
  const SphereComparison comparison = compareWithSphere(*result.grid, 3.0);
  EXPECT_GT(comparison.checkedSigns, 10000u);
  EXPECT_EQ(comparison.wrongSigns, 0u);
  // Deep inside and far outside.
  const auto accessor = result.grid->getConstAccessor();
  EXPECT_LT(accessor.getValue(openvdb::Coord(0, 0, 0)), 0.0f);
  EXPECT_GT(accessor.getValue(openvdb::Coord(0, 0, 40)), 0.0f);
}

TEST(MeshToLevelSet, OpenBowlIsInsideWhereItsWindingNumberIsAtLeastHalf) {
  // A sphere without its cap z > 0.6 R: OpenVDB's exterior sweep floods the whole inside; the
  // winding number keeps the deep part of the bowl inside and closes the opening smoothly.
  TriangleMesh mesh = test::makeIcosphere(kCenter, kRadius, 3);
  std::vector<TriangleMesh::Triangle> kept;
  for (const TriangleMesh::Triangle& t : mesh.triangles) {
    if (mesh.positions[t[0]].z() - kCenter.z() < 0.6 * kRadius) kept.push_back(t);
  }
  mesh.triangles = kept;
  LevelSetOptions options;
  options.voxelSize = 0.08;
  const LevelSetResult result = meshToLevelSet(mesh, options);
  EXPECT_TRUE(test::containsText(result.warnings, "not closed"));
  EXPECT_FALSE(test::containsText(result.warnings, "no voxel of the signed field is inside"));
  EXPECT_EQ(result.signs.holesClosed, 1u);
  EXPECT_GT(result.signs.correctedVoxels, 1000u);
  const test::WindingNumberReference winding(mesh);
  const test::SignCheck check =
      test::compareSignsWithWindingNumbers(*result.grid, winding, 1e-4 * options.voxelSize);
  EXPECT_GT(check.checked, 5000u);
  EXPECT_EQ(check.wrong, 0u);
  // Deep in the bowl, inside; far above the opening, outside.
  const auto accessor = result.grid->getConstAccessor();
  const auto at = [&](double z) {
    return accessor.getValue(
        openvdb::Coord::round(result.grid->worldToIndex(openvdb::Vec3d(0, 0, z))));
  };
  EXPECT_LT(at(-0.9), 0.0f);
  EXPECT_GT(at(1.3), 0.0f);
}

TEST(MeshToLevelSet, SheetHasNoInsideAndSaysSo) {
  // A flat sheet's winding number stays within (-1/2, 1/2): no voxel is inside.
  const TriangleMesh sheet = test::makeSquareSheet(1.0, 8);
  LevelSetOptions options;
  options.voxelSize = 0.05;
  const LevelSetResult result = meshToLevelSet(sheet, options);
  EXPECT_TRUE(test::containsText(result.warnings, "not closed"));
  EXPECT_TRUE(test::containsText(result.warnings, "no voxel of the signed field is inside"));
  for (auto voxel = result.grid->cbeginValueOn(); voxel; ++voxel) {
    if (std::abs(*voxel) < 1e-6f) continue;
    ASSERT_GT(*voxel, 0.0f) << voxel.getCoord();
  }
}

TEST(MeshToLevelSet, UnsignedDistanceToASheetIsExact) {
  const double half = 1.0;
  const TriangleMesh sheet = test::makeSquareSheet(half, 8);
  LevelSetOptions options;
  options.voxelSize = 0.05;
  options.unsignedDistance = true;
  const LevelSetResult result = meshToLevelSet(sheet, options);
  EXPECT_EQ(result.grid->getGridClass(), openvdb::GRID_UNKNOWN);
  EXPECT_EQ(result.grid->metaValue<std::string>(kDistanceKindMetadata), "unsigned");
  EXPECT_TRUE(result.warnings.empty());
  EXPECT_FLOAT_EQ(result.grid->background(), 0.15f);

  // Exact distance to the square [-1, 1]^2 x {0}.
  const auto exactDistance = [half](const openvdb::Vec3d& p) {
    const double dx = std::max(std::abs(p.x()) - half, 0.0);
    const double dy = std::max(std::abs(p.y()) - half, 0.0);
    return std::sqrt(dx * dx + dy * dy + p.z() * p.z());
  };
  double largestError = 0.0;
  for (auto voxel = result.grid->cbeginValueOn(); voxel; ++voxel) {
    EXPECT_GE(*voxel, 0.0f);
    EXPECT_LT(*voxel, 0.15f);
    const double exact = exactDistance(result.grid->indexToWorld(voxel.getCoord()));
    largestError = std::max(largestError, std::abs(double(*voxel) - exact));
  }
  EXPECT_LT(largestError, 1e-3 * options.voxelSize);
  // Band coverage: every voxel within 2.5 voxels of the sheet is active.
  const auto accessor = result.grid->getConstAccessor();
  std::size_t missing = 0;
  for (int i = -26; i <= 26; ++i) {
    for (int j = -26; j <= 26; ++j) {
      for (int k = -4; k <= 4; ++k) {
        const openvdb::Coord ijk(i, j, k);
        if (exactDistance(result.grid->indexToWorld(ijk)) < 2.5 * 0.05 &&
            !accessor.isValueOn(ijk)) {
          ++missing;
        }
      }
    }
  }
  EXPECT_EQ(missing, 0u);
}

TEST(MeshToLevelSet, OneAndTwoThreadsGiveBitwiseIdenticalGrids) {
  TriangleMesh mesh = test::makeIcosphere(kCenter, kRadius, 4);
  std::swap(mesh.triangles[7][0], mesh.triangles[7][1]);  // exercise the sign paths too
  LevelSetOptions options;
  options.voxelSize = 0.03;
  options.halfWidth = 4.0;
  const auto one = test::withThreads(1, [&] { return meshToLevelSet(mesh, options).grid; });
  const auto two = test::withThreads(2, [&] { return meshToLevelSet(mesh, options).grid; });
  test::expectBitwiseIdentical(*one, *two);
  options.unsignedDistance = true;
  const auto oneUnsigned = test::withThreads(1, [&] { return meshToLevelSet(mesh, options).grid; });
  const auto twoUnsigned = test::withThreads(2, [&] { return meshToLevelSet(mesh, options).grid; });
  test::expectBitwiseIdentical(*oneUnsigned, *twoUnsigned);
  // Few large triangles take OpenVDB's other path (triangles subdivided into parallel tasks).
  const TriangleMesh cube = test::makeUnitCube();
  LevelSetOptions cubeOptions;
  cubeOptions.resolution = 90;
  const auto oneCube = test::withThreads(1, [&] { return meshToLevelSet(cube, cubeOptions).grid; });
  const auto twoCube = test::withThreads(2, [&] { return meshToLevelSet(cube, cubeOptions).grid; });
  test::expectBitwiseIdentical(*oneCube, *twoCube);
}

/// The fractions reported for each stage, in the order the stages came (a stage never returns).
std::vector<std::pair<std::string, std::vector<double>>> progressOf(
    const TriangleMesh& mesh, const LevelSetOptions& options) {
  std::vector<std::pair<std::string, std::vector<double>>> stages;
  meshToLevelSet(mesh, options, [&](std::string_view stage, double fraction) {
    if (stages.empty() || stages.back().first != stage)
      stages.emplace_back(stage, std::vector<double>{});
    stages.back().second.push_back(fraction);
  });
  return stages;
}

void expectMonotoneFromZeroToOne(const std::vector<double>& fractions) {
  ASSERT_GE(fractions.size(), 2u);
  EXPECT_EQ(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);
}

TEST(MeshToLevelSet, ReportsMonotoneProgressEndingAtOne) {
  const TriangleMesh mesh = test::makeIcosphere(kCenter, kRadius, 3);
  LevelSetOptions options;
  options.voxelSize = kVoxel;
  // The conversion, then the sign pass as a stage of its own from its start.
  const auto stages = progressOf(mesh, options);
  ASSERT_EQ(stages.size(), 2u);
  EXPECT_EQ(stages[0].first, "mesh to level set");
  EXPECT_EQ(stages[1].first, "exact signs (closest feature)");
  expectMonotoneFromZeroToOne(stages[0].second);
  expectMonotoneFromZeroToOne(stages[1].second);
  EXPECT_GE(stages[1].second.size(), 10u);  // the pass reports as it goes
  // Without exact signs, the conversion alone.
  options.exactSigns = false;
  const auto unchecked = progressOf(mesh, options);
  ASSERT_EQ(unchecked.size(), 1u);
  EXPECT_EQ(unchecked[0].first, "mesh to level set");
  expectMonotoneFromZeroToOne(unchecked[0].second);
}

TEST(MeshToLevelSet, RejectsBadInput) {
  const TriangleMesh sphere = test::makeIcosphere(kCenter, kRadius, 1);
  LevelSetOptions good;
  good.voxelSize = 0.1;

  EXPECT_THROW(meshToLevelSet(TriangleMesh{}, good), InputError);
  TriangleMesh withNan = sphere;
  withNan.positions[3].y() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(meshToLevelSet(withNan, good), InputError);
  TriangleMesh badIndex = sphere;
  badIndex.triangles[0][1] = 100000;
  EXPECT_THROW(meshToLevelSet(badIndex, good), InputError);
  TriangleMesh point;
  point.positions.assign(3, Eigen::Vector3f(1, 2, 3));
  point.triangles.push_back({0, 1, 2});
  EXPECT_THROW(meshToLevelSet(point, good), InputError);

  LevelSetOptions options = good;
  options.voxelSize = -0.1;
  EXPECT_THROW(meshToLevelSet(sphere, options), InputError);
  options.voxelSize = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(meshToLevelSet(sphere, options), InputError);
  options.voxelSize = 0.0;
  options.resolution = 0;
  EXPECT_THROW(meshToLevelSet(sphere, options), InputError);
  options.resolution = -5;
  EXPECT_THROW(meshToLevelSet(sphere, options), InputError);
  options = good;
  options.halfWidth = 0.5;
  EXPECT_THROW(meshToLevelSet(sphere, options), InputError);
}

TEST(MeshToLevelSet, RefusesAHugeResolutionInstantly) {
  // A unit cube as 12 triangles, at a resolution of a million voxels per side.
  const TriangleMesh cube = test::makeUnitCube();
  LevelSetOptions options;
  options.resolution = 1'000'000;
  const auto start = std::chrono::steady_clock::now();
  try {
    meshToLevelSet(cube, options);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("12 triangles"), std::string::npos) << message;
    EXPECT_NE(message.find("limit"), std::string::npos) << message;
    EXPECT_NE(message.find("resolution of at most"), std::string::npos) << message;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(500));
  // The same cube at a modest resolution converts and has no warnings.
  options.resolution = 20;
  const LevelSetResult result = meshToLevelSet(cube, options);
  EXPECT_TRUE(result.meshReport.closed) << result.meshReport.problems();
  EXPECT_TRUE(result.warnings.empty());
  EXPECT_LT(result.grid->tree().getValue(openvdb::Coord(10, 10, 10)), 0.0f);
}

}  // namespace
}  // namespace d2vdb
