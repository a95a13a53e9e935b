// The voxels of a field's band: a distance grid, its index frame, and the leaf table that
// numbers its active voxels (the order of the band's records).
#pragma once

#include <openvdb/openvdb.h>

#include <string>

#include "d2vdb/field/detail/IndexFrame.h"
#include "d2vdb/field/detail/LeafTable.h"

namespace d2vdb::detail {

/// A band's voxels. Invariants (established by the constructor): the table holds exactly the
/// active voxels of the grid, leaf by leaf (by origin; leaves without active voxels have no
/// entry), so record i of a band belongs to the i-th voxel the table numbers; the grid has no
/// active tiles and at least one active voxel; the frame is the grid's transform. The grid is
/// shared and never modified.
class BandLayout {
 public:
  /// The layout of `grid`'s active voxels. Throws InputError, naming `source`, for a transform
  /// IndexFrame refuses, active tiles, or no active voxel.
  BandLayout(openvdb::FloatGrid::ConstPtr grid, const std::string& source);

  const openvdb::FloatGrid::ConstPtr& grid() const { return grid_; }
  const IndexFrame& frame() const { return frame_; }
  const LeafTable& table() const { return table_; }
  /// Number of band voxels.
  std::uint64_t voxelCount() const { return table_.voxelCount(); }
  /// Half-width of the band in voxels: |background| / voxel size.
  double halfWidth() const;

  /// Swaps in a grid with the same transform and active topology (e.g. a copy with other
  /// values); the table stays valid. Throws RuntimeFailure (a caller's bug) when they differ.
  void replaceGrid(openvdb::FloatGrid::ConstPtr sameTopology);

 private:
  openvdb::FloatGrid::ConstPtr grid_;
  IndexFrame frame_;
  LeafTable table_;
};

}  // namespace d2vdb::detail
