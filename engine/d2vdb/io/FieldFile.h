// Reading and writing squared-distance approximant fields (ApproximantField.h) as .vdb files.
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/io/FieldGrids.h"
#include "d2vdb/io/VdbFile.h"

namespace d2vdb {

/// Writes the field's grids (fieldToGrids(): the distance grid and its companion grids, all
/// standard OpenVDB types) to `path` atomically with writeVdb(). Throws InputError or
/// RuntimeFailure as writeVdb() does; an existing file is left unchanged on failure.
void writeField(const std::filesystem::path& path, const ApproximantField& field,
                const VdbWriteOptions& options = {});

/// Reads a .vdb file written by writeField() and rebuilds the field's band (files do not store the
/// coarse levels: the field builds them on its first query beyond the band, with the same
/// answers as before writing), or builds the field of a plain level set (e.g. from Houdini) as
/// ApproximantField::fromLevelSet() does. Throws InputError naming the file for an unreadable,
/// truncated or corrupt file, NaN values, and missing or mismatched companion grids
/// (fieldFromGrids()).
ApproximantField readField(const std::filesystem::path& path,
                           const ApproximantFieldOptions& options = {},
                           const ProgressCallback& progress = {});

/// True when `grids` hold a field written by writeField(): the grid findGrid() selects (the first
/// float level set, else the first float grid) carries the kFieldKindMetadata metadata. Never
/// throws.
bool isFieldFile(const std::vector<openvdb::GridBase::Ptr>& grids);

}  // namespace d2vdb
