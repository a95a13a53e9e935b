// Reading parts of a .vdb file: every grid, but only the voxels inside a box, for queries that
// need a small region of a large file.
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>
#include <vector>

namespace d2vdb {

/// Reads one .vdb file in parts. The constructor checks the whole file as readAllGrids() does
/// (a regular, non-empty file with the VDB magic number, then the bounds-checked walk of every
/// size and chunk in it) and reads the grids' metadata; read() then reads every grid clipped to a
/// box, skipping the leaves outside it without decompressing them (OpenVDB's clipped read,
/// openvdb::io::File::readGrid(name, bbox), from the memory-mapped file: only the pages of the
/// leaves read are touched; leaves inside the box load their values from the mapping when first
/// used). Throws InputError naming the file as readAllGrids() does. Not thread-safe.
class VdbPartialReader {
 public:
  explicit VdbPartialReader(const std::filesystem::path& path);

  /// Every grid of the file in file order, with metadata and transform but no voxels.
  const std::vector<openvdb::GridBase::Ptr>& metadata() const { return metadata_; }

  /// Every grid of the file in file order, holding only the voxels whose centres lie inside the
  /// world box `worldBox` (a voxel-exact clip: the voxels of leaves that straddle the box's
  /// boundary outside it are inactive background). Values are checked as in readAllGrids()
  /// (finite, a usable transform). Throws InputError naming the file.
  std::vector<openvdb::GridBase::Ptr> read(const openvdb::BBoxd& worldBox) const;

  /// Every grid of the file whole, from the memory-mapped file checked by the constructor (no
  /// second walk of the file, as readAllGrids() would make). Values are checked as in read().
  std::vector<openvdb::GridBase::Ptr> readAll() const;

 private:
  /// Every grid, clipped to `worldBox` unless it is null.
  std::vector<openvdb::GridBase::Ptr> readGrids(const openvdb::BBoxd* worldBox) const;

  std::filesystem::path path_;
  std::vector<openvdb::GridBase::Ptr> metadata_;
};

}  // namespace d2vdb
