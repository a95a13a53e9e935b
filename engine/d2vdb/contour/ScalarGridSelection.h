// Choosing the scalar grid to contour among the grids of a .vdb file.
#pragma once

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace d2vdb {

/// The grid to contour: the one named `gridName` if given (it must hold float or double
/// values), otherwise the first float or double grid of class level set, otherwise the first
/// float or double grid. Throws InputError naming `source` (e.g. the file) and listing the grids
/// present (name, value type) when none fits.
openvdb::GridBase::Ptr selectScalarGrid(const std::vector<openvdb::GridBase::Ptr>& grids,
                                        const std::string& gridName, const std::string& source);

}  // namespace d2vdb
