// Internal to the io module: reading every grid of .vdb data from a stream, checked.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace d2vdb::detail {

/// Reads every grid of the .vdb data of `size` bytes readable from `in` (positioned at the data's
/// first byte, seekable): first the bounds-checked walk of checkVdbStream (VdbFormatCheck.h), then
/// OpenVDB's own reader, then the checks of readAllGrids (finite values, a usable transform).
/// `name` stands for the file in messages. Throws InputError as readAllGrids does.
std::vector<openvdb::GridBase::Ptr> readVdbStream(std::istream& in, std::uint64_t size,
                                                  const std::string& name);

}  // namespace d2vdb::detail
