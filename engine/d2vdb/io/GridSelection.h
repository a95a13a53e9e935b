// Which grid of a .vdb file a command works on: one rule for every reader of grids.
#pragma once

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace d2vdb {

/// The value types a selected grid may hold.
enum class ScalarGridTypes {
  Float,          ///< openvdb::FloatGrid only (level sets, fields)
  FloatOrDouble,  ///< openvdb::FloatGrid or openvdb::DoubleGrid (contouring)
};

/// The grid to use among `grids` (in file order): the grid named `gridName` when it is not empty,
/// otherwise the first grid of class level set holding an accepted value type, otherwise the first
/// grid holding an accepted value type. Returns nullptr when none fits; null entries are skipped.
/// A grid named `gridName` that holds another value type is not returned (selectGrid() says why).
/// Never throws.
openvdb::GridBase::Ptr findGrid(const std::vector<openvdb::GridBase::Ptr>& grids,
                                const std::string& gridName = "",
                                ScalarGridTypes types = ScalarGridTypes::Float);

/// findGrid(), but never null: throws InputError naming `source` (e.g. "'bunny.vdb'") when no grid
/// fits, saying whether the named grid is missing or holds the wrong value type, and listing the
/// grids present with their value type and class.
openvdb::GridBase::Ptr selectGrid(const std::vector<openvdb::GridBase::Ptr>& grids,
                                  const std::string& source, const std::string& gridName = "",
                                  ScalarGridTypes types = ScalarGridTypes::Float);

/// The grids as "'name' (value type, class), ..." for messages ("none" when there are none).
std::string describeGrids(const std::vector<openvdb::GridBase::Ptr>& grids);

}  // namespace d2vdb
