// Narrow-band level sets of analytic shapes, with exact distances at every band voxel.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>

#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/VoxelBudget.h"

namespace d2vdb {

/// Parameters of primitiveLevelSet().
struct PrimitiveLevelSetOptions {
  double voxelSize = 0;  ///< world units; must be finite and positive
  double halfWidth = 3;  ///< narrow-band half-width in voxels; at least 1
  std::uint64_t maxActiveVoxels = kDefaultMaxActiveVoxels;  ///< see VoxelBudget.h
  /// Refuse level sets whose estimated memory (kLevelSetPeakBytesPerVoxel per estimated active
  /// voxel) exceeds this many bytes; 0 = no limit.
  std::uint64_t maxMemoryBytes = kDefaultMaxMemoryBytes;
};

/// Builds the narrow-band level set of `shape`:
/// - a linear transform with the voxel size; voxel (i, j, k) has its centre at
///   (i, j, k) * voxelSize in world space (OpenVDB's cell-centred convention);
/// - every voxel whose exact signed distance satisfies |d| < halfWidth * voxelSize is active and
///   holds d (world units, negative inside, rounded to float); no other voxel is active;
/// - background = halfWidth * voxelSize; inactive voxels and tiles inside the solid hold
///   -background (signed flood fill), those outside +background;
/// - grid class GRID_LEVEL_SET, name "surface".
/// Work runs in parallel over 8^3 leaf blocks, skipping any block whose centre distance proves it
/// holds no band voxel; the result is bitwise identical for any thread count.
/// Throws InputError for a non-positive voxel size, halfWidth < 1, a grid that would not fit
/// OpenVDB's 32-bit coordinates, or (before allocating anything) an estimated active voxel count
/// above options.maxActiveVoxels.
openvdb::FloatGrid::Ptr primitiveLevelSet(const AnalyticShape& shape,
                                          const PrimitiveLevelSetOptions& options);

}  // namespace d2vdb
