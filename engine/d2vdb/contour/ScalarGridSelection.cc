// Selection of the grid to contour (ScalarGridSelection.h).
#include "d2vdb/contour/ScalarGridSelection.h"

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

bool isScalar(const openvdb::GridBase& grid) {
  return grid.isType<openvdb::FloatGrid>() || grid.isType<openvdb::DoubleGrid>();
}

std::string listGrids(const std::vector<openvdb::GridBase::Ptr>& grids) {
  std::string list;
  for (const auto& grid : grids) {
    if (!grid) continue;
    list += (list.empty() ? "" : ", ") + ("'" + grid->getName() + "' (" + grid->valueType() + ")");
  }
  return list.empty() ? "none" : list;
}

}  // namespace

openvdb::GridBase::Ptr selectScalarGrid(const std::vector<openvdb::GridBase::Ptr>& grids,
                                        const std::string& gridName, const std::string& source) {
  if (!gridName.empty()) {
    for (const auto& grid : grids) {
      if (!grid || grid->getName() != gridName) continue;
      if (!isScalar(*grid)) {
        throw InputError(source + ": grid '" + gridName + "' holds " + grid->valueType() +
                         " values; a float or double grid is needed");
      }
      return grid;
    }
    throw InputError(source + " has no grid named '" + gridName +
                     "'; its grids: " + listGrids(grids));
  }
  for (const auto& grid : grids) {
    if (grid && isScalar(*grid) && grid->getGridClass() == openvdb::GRID_LEVEL_SET) return grid;
  }
  for (const auto& grid : grids) {
    if (grid && isScalar(*grid)) return grid;
  }
  throw InputError(source + " holds no float or double grid; its grids: " + listGrids(grids));
}

}  // namespace d2vdb
