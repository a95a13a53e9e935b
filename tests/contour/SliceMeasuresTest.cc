// The middle plane of a grid's active voxels, against bounding boxes worked out by hand, and the
// line counts of slices.
#include "d2vdb/contour/SliceMeasures.h"

#include <gtest/gtest.h>

#include <optional>

#include "common/ExpectInputError.h"
#include "d2vdb/field/Primitives.h"

namespace d2vdb::test {
namespace {

/// A grid with voxel size 0.5 whose active voxels are (-3, 0, 0) and (5, 2, -7): their index box
/// is [-3, 5] x [0, 2] x [-7, 0] with centre (1, 1, -3.5), i.e. (0.5, 0.5, -1.75) in world units.
template <typename GridT>
typename GridT::Ptr twoVoxelGrid() {
  const typename GridT::Ptr grid = GridT::create(1);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
  grid->tree().setValueOn(openvdb::Coord(-3, 0, 0), 0);
  grid->tree().setValueOn(openvdb::Coord(5, 2, -7), 0);
  return grid;
}

TEST(SliceMeasures, OffsetIsTheCenterOfTheActiveVoxelBox) {
  const openvdb::FloatGrid::Ptr grid = twoVoxelGrid<openvdb::FloatGrid>();
  EXPECT_EQ(activeVoxelCenterOffset(*grid, 0), 0.5);
  EXPECT_EQ(activeVoxelCenterOffset(*grid, 1), 0.5);
  EXPECT_EQ(activeVoxelCenterOffset(*grid, 2), -1.75);

  // A translated transform moves the plane with it: world = 0.5 index + (1, 2, 3).
  grid->transform().postTranslate(openvdb::Vec3d(1, 2, 3));
  EXPECT_EQ(activeVoxelCenterOffset(*grid, 0), 1.5);
  EXPECT_EQ(activeVoxelCenterOffset(*grid, 1), 2.5);
  EXPECT_EQ(activeVoxelCenterOffset(*grid, 2), 1.25);

  const openvdb::DoubleGrid::Ptr doubles = twoVoxelGrid<openvdb::DoubleGrid>();
  EXPECT_EQ(activeVoxelCenterOffset(*doubles, 2), -1.75);
}

TEST(SliceMeasures, SphereOffsetIsItsCenter) {
  PrimitiveLevelSetOptions levelSet;
  levelSet.voxelSize = 0.125;  // the centre is a grid point, the band symmetric about it
  const auto grid = primitiveLevelSet(Sphere(Eigen::Vector3d(1.0, -2.0, 0.5), 1.0), levelSet);
  EXPECT_NEAR(*activeVoxelCenterOffset(*grid, 0), 1.0, 1e-12);
  EXPECT_NEAR(*activeVoxelCenterOffset(*grid, 1), -2.0, 1e-12);
  EXPECT_NEAR(*activeVoxelCenterOffset(*grid, 2), 0.5, 1e-12);
}

TEST(SliceMeasures, EmptyGridHasNoOffsetAndBadAxesAreRejected) {
  EXPECT_EQ(activeVoxelCenterOffset(*openvdb::FloatGrid::create(1), 2), std::nullopt);
  const openvdb::FloatGrid::Ptr grid = twoVoxelGrid<openvdb::FloatGrid>();
  expectInputError([&] { activeVoxelCenterOffset(*grid, 3); }, {"axis"});
  expectInputError([&] { activeVoxelCenterOffset(*grid, -1); }, {"axis"});
}

TEST(SliceMeasures, CountsLinesClosedLinesAndPoints) {
  EXPECT_EQ(countSliceLines(Slice{}).lines, 0u);
  Slice slice;
  slice.lines.resize(3);
  slice.lines[0].points.resize(4);
  slice.lines[0].closed = true;
  slice.lines[1].points.resize(3);
  slice.lines[2].points.resize(5);
  slice.lines[2].closed = true;
  const SliceLineCounts counts = countSliceLines(slice);
  EXPECT_EQ(counts.lines, 3u);
  EXPECT_EQ(counts.closedLines, 2u);
  EXPECT_EQ(counts.points, 12u);
}

}  // namespace
}  // namespace d2vdb::test
