// What the contouring sub-commands (mesh, slice) share: the grid of a .vdb file they contour,
// chosen by --grid, and the --iso value.
#pragma once

#include <openvdb/openvdb.h>
#include <CLI/CLI.hpp>

#include <string>

namespace d2vdb::cli {

/// Declares --iso (into `isoValue`, grid value units) and --grid (into `gridName`).
void declareIsoAndGridOptions(CLI::App& command, double& isoValue, std::string& gridName);

/// The float or double grid named `gridName` of the .vdb file `input` (empty name: the first
/// float or double level set), for 'd2vdb `commandName`'. Throws InputError as loadInput() does.
openvdb::GridBase::Ptr loadContourGrid(const std::string& input, const std::string& gridName,
                                       const std::string& commandName);

}  // namespace d2vdb::cli
