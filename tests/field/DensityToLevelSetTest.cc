// Level sets of the iso-surfaces of density grids (DensityToLevelSet.h): a sphere's fog volume
// (OpenVDB's sdfToFogVolume of its exact level set, density rising linearly inward) rebuilt at an
// iso-value gives the sphere whose radius that iso-value implies, signed negative inside; signed
// distances rebuilt at an offset give the offset sphere; grids without a surface at the iso-value
// are refused.
#include "d2vdb/field/DensityToLevelSet.h"

#include <gtest/gtest.h>
#include <openvdb/tools/LevelSetUtil.h>

#include <cmath>

#include "common/ExpectInputError.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"

namespace d2vdb {
namespace {

constexpr double kDensityVoxel = 0.05;

// Largest |value - (|x| - radius)| in voxels over the band voxels of `levelSet` whose value lies
// within `within` voxels of the surface.
double worstSphereError(const openvdb::FloatGrid& levelSet, double radius, double within) {
  double worst = 0.0;
  for (auto value = levelSet.cbeginValueOn(); value; ++value) {
    if (std::abs(*value) > within * kDensityVoxel) continue;
    const openvdb::Vec3d p = levelSet.indexToWorld(value.getCoord());
    worst = std::max(worst, std::abs(*value - (p.length() - radius)) / kDensityVoxel);
  }
  return worst;
}

TEST(DensityToLevelSet, FogVolumeOfASphereBecomesTheSphereOfItsIsoValue) {
  const openvdb::FloatGrid::Ptr fog =
      primitiveLevelSet(Sphere({0, 0, 0}, 1.0), {kDensityVoxel, 3.0});
  const float cutoff = static_cast<float>(3.0 * kDensityVoxel);  // the band's inner half-width
  openvdb::tools::sdfToFogVolume(*fog, cutoff);  // density -d / cutoff inside, 0 outside
  ASSERT_TRUE(holdsDensity(*fog));
  const openvdb::FloatGrid::Ptr levelSet = levelSetOfIsoSurface(*fog, 0.5, 3.0);
  EXPECT_EQ(levelSet->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_FALSE(holdsDensity(*levelSet));
  // density 0.5 where d = -cutoff / 2: the sphere of radius 1 - cutoff / 2.
  // Distances to the meshed iso-surface: exact within two voxels of it; meshToVolume's sweep
  // makes the outermost layer of the band approximate.
  EXPECT_LT(worstSphereError(*levelSet, 1.0 - 0.5 * cutoff, 2.0), 0.1);
  EXPECT_LT(worstSphereError(*levelSet, 1.0 - 0.5 * cutoff, 3.0), 0.6);
  EXPECT_LT(levelSet->tree().getValue(openvdb::Coord(0, 0, 0)), 0.0f);   // inside
  EXPECT_GT(levelSet->tree().getValue(openvdb::Coord(40, 0, 0)), 0.0f);  // outside
  EXPECT_GT(levelSet->activeVoxelCount(), 0u);
}

TEST(DensityToLevelSet, SignedDistancesAtAnOffsetGiveTheOffsetSurface) {
  const openvdb::FloatGrid::Ptr sphere =
      primitiveLevelSet(Sphere({0, 0, 0}, 1.0), {kDensityVoxel, 3.0});
  ASSERT_FALSE(holdsDensity(*sphere));
  const openvdb::FloatGrid::Ptr offset = levelSetOfIsoSurface(*sphere, kDensityVoxel, 3.0);
  EXPECT_LT(worstSphereError(*offset, 1.0 + kDensityVoxel, 2.0), 0.1);
  EXPECT_LT(worstSphereError(*offset, 1.0 + kDensityVoxel, 3.0), 0.6);
  EXPECT_LT(offset->tree().getValue(openvdb::Coord(0, 0, 0)), 0.0f);
}

TEST(DensityToLevelSet, NoSurfaceAtTheIsoValueIsRefused) {
  const openvdb::FloatGrid::Ptr fog =
      primitiveLevelSet(Sphere({0, 0, 0}, 1.0), {kDensityVoxel, 3.0});
  openvdb::tools::sdfToFogVolume(*fog, static_cast<float>(3.0 * kDensityVoxel));
  test::expectInputError([&] { levelSetOfIsoSurface(*fog, 1.5); }, {"no surface at iso-value 1.5"});
  test::expectInputError([&] { levelSetOfIsoSurface(*fog, std::nan("")); }, {"finite"});
  const openvdb::FloatGrid::Ptr empty = openvdb::FloatGrid::create(0.0f);
  test::expectInputError([&] { levelSetOfIsoSurface(*empty, 0.5); }, {"no active value"});
}

}  // namespace
}  // namespace d2vdb
