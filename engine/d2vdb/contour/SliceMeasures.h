// Measures of slices: the plane through the middle of a grid's active voxels, and how many lines
// and points a slice has.
#pragma once

#include <openvdb/openvdb.h>

#include <cstddef>
#include <optional>

#include "d2vdb/contour/IsoLines.h"

namespace d2vdb {

/// The offset (SliceOptions::offset, world units) of the plane normal to `axis` (0 = x, 1 = y,
/// 2 = z) through the middle of `grid`'s active voxels: the world coordinate along `axis` of the
/// centre of their index-space bounding box (openvdb::CoordBBox::getCenter()) mapped by the
/// grid's transform. std::nullopt when the grid has no active voxel. Throws InputError for an
/// axis outside 0..2.
std::optional<double> activeVoxelCenterOffset(const openvdb::GridBase& grid, int axis);

/// How many lines a slice holds, how many of them are closed, and their points in total.
struct SliceLineCounts {
  std::size_t lines = 0;
  std::size_t closedLines = 0;
  std::size_t points = 0;  ///< over all lines (a closed line does not repeat its first point)
};

/// The counts of `slice`. Never throws.
SliceLineCounts countSliceLines(const Slice& slice);

}  // namespace d2vdb
