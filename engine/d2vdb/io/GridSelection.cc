#include "d2vdb/io/GridSelection.h"

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

bool holdsAcceptedType(const openvdb::GridBase& grid, ScalarGridTypes types) {
  return grid.isType<openvdb::FloatGrid>() ||
         (types == ScalarGridTypes::FloatOrDouble && grid.isType<openvdb::DoubleGrid>());
}

const char* acceptedTypeNames(ScalarGridTypes types) {
  return types == ScalarGridTypes::Float ? "float" : "float or double";
}

openvdb::GridBase::Ptr findNamed(const std::vector<openvdb::GridBase::Ptr>& grids,
                                 const std::string& gridName) {
  for (const openvdb::GridBase::Ptr& grid : grids) {
    if (grid && grid->getName() == gridName) return grid;
  }
  return nullptr;
}

}  // namespace

openvdb::GridBase::Ptr findGrid(const std::vector<openvdb::GridBase::Ptr>& grids,
                                const std::string& gridName, ScalarGridTypes types) {
  if (!gridName.empty()) {
    openvdb::GridBase::Ptr named = findNamed(grids, gridName);
    return named && holdsAcceptedType(*named, types) ? named : nullptr;
  }
  for (const openvdb::GridBase::Ptr& grid : grids) {
    if (grid && holdsAcceptedType(*grid, types) &&
        grid->getGridClass() == openvdb::GRID_LEVEL_SET) {
      return grid;
    }
  }
  for (const openvdb::GridBase::Ptr& grid : grids) {
    if (grid && holdsAcceptedType(*grid, types)) return grid;
  }
  return nullptr;
}

openvdb::GridBase::Ptr selectGrid(const std::vector<openvdb::GridBase::Ptr>& grids,
                                  const std::string& source, const std::string& gridName,
                                  ScalarGridTypes types) {
  if (openvdb::GridBase::Ptr grid = findGrid(grids, gridName, types)) return grid;
  if (!gridName.empty()) {
    if (const openvdb::GridBase::Ptr named = findNamed(grids, gridName)) {
      throw InputError("grid '" + gridName + "' in " + source + " holds " + named->valueType() +
                       " values; a " + acceptedTypeNames(types) + " grid is needed");
    }
    throw InputError(source + " has no grid named '" + gridName +
                     "'; its grids are: " + describeGrids(grids));
  }
  throw InputError(source + " holds no " + acceptedTypeNames(types) +
                   " grid; its grids are: " + describeGrids(grids));
}

std::string describeGrids(const std::vector<openvdb::GridBase::Ptr>& grids) {
  std::string list;
  for (const openvdb::GridBase::Ptr& grid : grids) {
    if (!grid) continue;
    list += (list.empty() ? "'" : ", '") + grid->getName() + "' (" + grid->valueType() + ", " +
            openvdb::GridBase::gridClassToString(grid->getGridClass()) + ")";
  }
  return list.empty() ? "none" : list;
}

}  // namespace d2vdb
