#include "d2vdb/field/DensityToLevelSet.h"

#include <openvdb/tools/LevelSetRebuild.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "d2vdb/core/Error.h"

namespace d2vdb {

bool holdsDensity(const openvdb::FloatGrid& grid) {
  if (grid.getGridClass() == openvdb::GRID_FOG_VOLUME) return true;
  if (grid.getGridClass() != openvdb::GRID_UNKNOWN || grid.background() != 0.0f) return false;
  for (auto value = grid.cbeginValueOn(); value; ++value) {
    if (*value < 0.0f) return false;
  }
  return true;
}

openvdb::FloatGrid::Ptr levelSetOfIsoSurface(const openvdb::FloatGrid& grid, double iso,
                                             double halfWidth) {
  if (!std::isfinite(iso)) throw InputError("the iso-value must be a finite number");
  if (!(halfWidth >= 1.0)) throw InputError("the band's half-width must be at least 1 voxel");
  float low = std::numeric_limits<float>::infinity(), high = -low;
  for (auto value = grid.cbeginValueOn(); value; ++value) {
    low = std::min(low, *value);
    high = std::max(high, *value);
  }
  if (!(low < iso && iso < high)) {
    std::ostringstream message;
    message.precision(6);
    message << "grid '" << grid.getName() << "' has no surface at iso-value " << iso;
    if (low <= high)
      message << ": its active values span [" << low << ", " << high << "]";
    else
      message << ": it has no active value";
    throw InputError(message.str());
  }
  // levelSetRebuild takes the values below the iso-value as inside; a density is inside above it.
  openvdb::FloatGrid::Ptr levelSet;
  const float width = static_cast<float>(halfWidth);
  if (holdsDensity(grid)) {
    const openvdb::FloatGrid::Ptr negated = grid.deepCopy();
    for (auto value = negated->beginValueAll(); value; ++value) value.setValue(-*value);
    negated->tree().root().setBackground(-grid.background(), /*updateChildNodes=*/true);
    levelSet = openvdb::tools::levelSetRebuild(*negated, static_cast<float>(-iso), width);
  } else {
    levelSet = openvdb::tools::levelSetRebuild(grid, static_cast<float>(iso), width);
  }
  levelSet->setGridClass(openvdb::GRID_LEVEL_SET);
  levelSet->setName(grid.getName());
  return levelSet;
}

}  // namespace d2vdb
