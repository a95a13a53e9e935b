// Internal to the io module: a bounds-checked walk over a whole .vdb stream, done before OpenVDB
// is allowed to read it.
//
// OpenVDB 10's readers trust every length and count in a file: a chunk size, a string length, a
// node mask or a metadata count read from a corrupt file makes them allocate gigabytes or write
// past a buffer (io::bloscFromStream copies a chunk of the size the file states into a buffer of
// the size the node needs). This walk reads the stream exactly as io::Stream does, for the file
// format versions 222 to 224 (OpenVDB 3.0 to today) and the grid types every OpenVDB build
// registers, and checks each value against the bytes left and against what the reader will do
// with it, so that the read that follows can only act on consistent data.
#pragma once

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace d2vdb::detail {

/// What the walk found in one grid.
struct VdbGridLayout {
  std::string name;  ///< the descriptor's unique name
  std::string type;  ///< OpenVDB's grid type name, e.g. "Tree_float_5_4_3"
  bool instance = false;
  std::uint64_t internalNodes = 0;  ///< nodes below the root (both internal levels)
  std::uint64_t leafNodes = 0;
  /// Bytes the grid's tree takes once OpenVDB has read it (node storage, an upper estimate).
  std::uint64_t treeBytes = 0;
};

/// Walks the .vdb data of `size` bytes readable from `in` (positioned at its first byte) and throws
/// InputError "'<name>' is truncated or corrupt: <what> (at byte <offset> of <size>)", or "'<name>'
/// ... not supported" for a valid file d2vdb does not read (file format before 222 or after 224, a
/// grid type other than bool, mask, float, double, int32, int64, vec3s, vec3d and vec3i grids, a
/// registered metadata type it does not know, a frustum transform nested in another). Checks:
/// every string, metadata value, node mask and compressed chunk lies within the stream; Blosc
/// chunks are valid (blosc_cbuffer_validate) and, like zlib chunks, decompress to exactly the
/// bytes the node needs; counts and sizes agree with the node masks; root tiles and children sit
/// on their node grid, in increasing order, within +-2^30 voxels; internal nodes have no slot that
/// is both a child and an active value; bool values are 0 or 1; the grid offsets of the descriptors
/// match the data; no bytes follow the last grid. Everything OpenVDB allocates while reading is
/// then backed by bytes of the stream (see VdbGridLayout::treeBytes). Leaves `in` at an
/// unspecified position.
std::vector<VdbGridLayout> checkVdbStream(std::istream& in, std::uint64_t size,
                                          const std::string& name);

}  // namespace d2vdb::detail
