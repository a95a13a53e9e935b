#include "d2vdb/contour/SliceMeasures.h"

#include "d2vdb/core/Error.h"

namespace d2vdb {

std::optional<double> activeVoxelCenterOffset(const openvdb::GridBase& grid, int axis) {
  if (axis < 0 || axis > 2) throw InputError("the slice axis must be x, y or z (0, 1 or 2)");
  const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
  if (box.empty()) return std::nullopt;
  return grid.indexToWorld(box.getCenter())[axis];
}

SliceLineCounts countSliceLines(const Slice& slice) {
  SliceLineCounts counts;
  counts.lines = slice.lines.size();
  for (const IsoLine& line : slice.lines) {
    counts.closedLines += line.closed ? 1 : 0;
    counts.points += line.points.size();
  }
  return counts;
}

}  // namespace d2vdb
