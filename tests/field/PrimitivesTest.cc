// Primitive level sets: exact values at every band voxel, exact band coverage, signs of every
// voxel and tile, determinism across thread counts, and refusals.
#include "d2vdb/field/Primitives.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "d2vdb/core/Error.h"
#include "field/FieldTestSupport.h"

namespace d2vdb {
namespace {

// Visits every voxel of the shape's bounding box grown by the band and two voxels, and checks:
// active exactly where |d| < band; active values equal the exact distance up to float rounding;
// every other value (inactive voxel or tile) is +-background with the sign of d.
// Returns how many checked voxels lie inside the solid beyond the band.
std::uint64_t expectExactNarrowBand(const AnalyticShape& shape, const openvdb::FloatGrid& grid,
                                    double voxelSize, double halfWidth) {
  const double band = halfWidth * voxelSize;
  const float background = static_cast<float>(band);
  EXPECT_EQ(grid.getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(grid.getName(), "surface");
  EXPECT_EQ(grid.background(), background);
  EXPECT_TRUE(grid.transform().isLinear());
  EXPECT_EQ(grid.voxelSize(), openvdb::Vec3d(voxelSize));
  EXPECT_EQ(grid.indexToWorld(openvdb::Coord(3, -4, 5)),
            openvdb::Vec3d(3 * voxelSize, -4 * voxelSize, 5 * voxelSize));

  const Eigen::AlignedBox3d bounds = shape.bounds();
  openvdb::Coord lo;
  openvdb::Coord hi;
  for (int axis = 0; axis < 3; ++axis) {
    lo[axis] = static_cast<int>(std::floor((bounds.min()[axis] - band) / voxelSize)) - 2;
    hi[axis] = static_cast<int>(std::ceil((bounds.max()[axis] + band) / voxelSize)) + 2;
  }
  const auto accessor = grid.getConstAccessor();
  std::uint64_t expectedActive = 0;
  std::uint64_t wrongActivity = 0;
  std::uint64_t wrongInactiveValue = 0;
  double largestError = 0.0;
  std::uint64_t interiorOutsideBand = 0;
  for (int i = lo.x(); i <= hi.x(); ++i) {
    for (int j = lo.y(); j <= hi.y(); ++j) {
      for (int k = lo.z(); k <= hi.z(); ++k) {
        const openvdb::Coord ijk(i, j, k);
        const double d = shape.signedDistance(Eigen::Vector3d(i, j, k) * voxelSize);
        const bool inBand = std::abs(d) < band;
        float value = 0.0f;
        const bool active = accessor.probeValue(ijk, value);
        if (active != inBand) ++wrongActivity;
        if (inBand) {
          ++expectedActive;
          largestError = std::max(largestError, std::abs(double(value) - d));
        } else {
          if (d < 0.0) ++interiorOutsideBand;
          if (value != (d < 0.0 ? -background : background)) ++wrongInactiveValue;
        }
      }
    }
  }
  EXPECT_EQ(wrongActivity, 0u) << shape.describe();
  EXPECT_EQ(wrongInactiveValue, 0u) << shape.describe();
  EXPECT_EQ(grid.activeVoxelCount(), expectedActive) << "active voxels outside the checked box";
  EXPECT_LE(largestError, 1e-6 * voxelSize) << shape.describe();
  EXPECT_GT(expectedActive, 0u);
  // Far away, the tree answers with the background, outside positive.
  EXPECT_EQ(accessor.getValue(hi.offsetBy(1000)), background);
  return interiorOutsideBand;
}

TEST(Primitives, SphereIsExactEverywhere) {
  const Sphere sphere({0.1, -0.2, 0.05}, 1.5);
  const double voxelSize = 0.05;  // radius = 30 voxels: the interior has whole-leaf tiles
  const openvdb::FloatGrid::Ptr grid = primitiveLevelSet(sphere, {voxelSize, 3.0});
  // About 4/3 pi 27^3 voxels inside beyond the band, most of them in flood-filled tiles.
  EXPECT_GT(expectExactNarrowBand(sphere, *grid, voxelSize, 3.0), 70000u);
  EXPECT_EQ(grid->tree().getValue(openvdb::Coord(2, -4, 1)), -grid->background());
  EXPECT_EQ(grid->tree().activeTileCount(), 0u);  // a narrow band has no active tiles
}

TEST(Primitives, BoxTorusAndCylinderAreExactEverywhere) {
  const Box box({-0.7, -0.3, -0.45}, {0.55, 0.4, 0.3});
  expectExactNarrowBand(box, *primitiveLevelSet(box, {0.05, 3.0}), 0.05, 3.0);
  const Torus torus({0.05, 0.0, -0.1}, 1.0, 0.35);
  expectExactNarrowBand(torus, *primitiveLevelSet(torus, {0.04, 3.0}), 0.04, 3.0);
  const CappedCylinder cylinder({0.0, 0.1, 0.0}, 0.5, 1.2);
  expectExactNarrowBand(cylinder, *primitiveLevelSet(cylinder, {0.04, 3.0}), 0.04, 3.0);
}

TEST(Primitives, OtherHalfWidths) {
  const Torus torus({0.0, 0.0, 0.0}, 1.0, 0.4);
  expectExactNarrowBand(torus, *primitiveLevelSet(torus, {0.05, 1.0}), 0.05, 1.0);
  expectExactNarrowBand(torus, *primitiveLevelSet(torus, {0.05, 5.5}), 0.05, 5.5);
}

TEST(Primitives, ShapeAwayFromTheOriginAndNegativeCoordinates) {
  const Sphere sphere({-13.37, 7.1, -2.2}, 0.8);
  expectExactNarrowBand(sphere, *primitiveLevelSet(sphere, {0.03, 3.0}), 0.03, 3.0);
}

TEST(Primitives, OneAndTwoThreadsGiveBitwiseIdenticalGrids) {
  const Torus torus({0.01, 0.02, 0.03}, 1.0, 0.3);
  const PrimitiveLevelSetOptions options{0.02, 3.0};
  const auto one = test::withThreads(1, [&] { return primitiveLevelSet(torus, options); });
  const auto two = test::withThreads(2, [&] { return primitiveLevelSet(torus, options); });
  test::expectBitwiseIdentical(*one, *two);
}

TEST(Primitives, RefusesHugeRequestsInstantlyWithAHelpfulMessage) {
  const Sphere unitSphere({0, 0, 0}, 1.0);
  const auto start = std::chrono::steady_clock::now();
  try {
    primitiveLevelSet(unitSphere, {1e-6, 3.0});
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("limit"), std::string::npos) << message;
    EXPECT_NE(message.find("voxel size of at least"), std::string::npos) << message;
    EXPECT_NE(message.find("sphere"), std::string::npos) << message;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(500));

  // A custom limit: the band of about 2.8e4 voxels is estimated at 4.2e4 (VoxelBudget.h).
  PrimitiveLevelSetOptions small{0.05, 3.0};
  small.maxActiveVoxels = 1000;
  EXPECT_THROW(primitiveLevelSet(unitSphere, small), InputError);
  small.maxActiveVoxels = 45000;
  EXPECT_NO_THROW(primitiveLevelSet(unitSphere, small));
}

TEST(Primitives, RejectsBadOptions) {
  const Sphere sphere({0, 0, 0}, 1.0);
  EXPECT_THROW(primitiveLevelSet(sphere, {0.0, 3.0}), InputError);
  EXPECT_THROW(primitiveLevelSet(sphere, {-0.1, 3.0}), InputError);
  EXPECT_THROW(primitiveLevelSet(sphere, {std::nan(""), 3.0}), InputError);
  EXPECT_THROW(primitiveLevelSet(sphere, {0.1, 0.5}), InputError);
  EXPECT_THROW(primitiveLevelSet(sphere, {0.1, std::nan("")}), InputError);
  // Beyond OpenVDB's coordinate range.
  const Sphere far({3e9, 0, 0}, 1.0);
  EXPECT_THROW(primitiveLevelSet(far, {1.0, 3.0}), InputError);
}

}  // namespace
}  // namespace d2vdb
