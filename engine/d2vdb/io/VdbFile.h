// Reading and writing .vdb files with the pipeline's conventions (grid names, metadata, checks).
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace d2vdb {

/// Grid metadata written by writeVdb(): the narrow-band half-width in voxels (double).
inline constexpr const char* kHalfWidthMetadata = "d2vdb_half_width";
/// Grid metadata written by writeVdb(): where the grid came from (string, e.g. an input file).
inline constexpr const char* kSourceMetadata = "d2vdb_source";

/// Reads every grid of a .vdb file completely into memory (no delayed loading, no memory
/// mapping), so that a truncated or corrupt file fails here and not later. Checks first that the
/// path is an existing, non-empty regular file starting with the VDB magic number. Floating-point
/// grids (float, double, Vec3s, Vec3d) must hold only finite values.
/// Throws InputError naming the file for: a missing, empty, non-VDB, truncated or corrupt file,
/// a file without grids, and non-finite values (with their count and one location).
std::vector<openvdb::GridBase::Ptr> readAllGrids(const std::filesystem::path& path);

/// Reads one float level set from a .vdb file (written by d2vdb or any OpenVDB tool), chosen by
/// selectGrid() (GridSelection.h): the grid named `gridName` if given (it must be a float grid),
/// otherwise the first float grid of class level set, otherwise the first float grid. Same checks
/// as readAllGrids(); throws InputError listing the grids present (name, value type, class) when
/// none fits.
openvdb::FloatGrid::Ptr readLevelSet(const std::filesystem::path& path,
                                     const std::string& gridName = "");

/// Options of writeVdb().
struct VdbWriteOptions {
  /// Blosc compression (fast, lossless). When libopenvdb lacks Blosc, zlib is used instead;
  /// with `blosc` false the values are stored uncompressed (inactive values still mask-compressed).
  bool blosc = true;
  /// Store float and Vec3s grids, background included, as 16-bit half floats (lossy: relative
  /// error up to 2^-11; magnitudes beyond 65504 become infinite). Grids in memory are unchanged.
  bool halfFloat = false;
  std::string source;    ///< written as kSourceMetadata when non-empty
  double halfWidth = 0;  ///< voxels; written as kHalfWidthMetadata when > 0 (see writeVdb)
};

/// Writes `grids` to `path` atomically (a temporary beside the target, renamed on success).
/// Grids are written from shallow copies, so the caller's grids and metadata are not modified.
/// Each written grid gets: metadata "creator" = "d2vdb <version>"; kSourceMetadata when
/// options.source is set; kHalfWidthMetadata = options.halfWidth when positive, otherwise, for
/// float/double level sets, background / voxel size; kDistanceKindMetadata
/// (field/MeshToLevelSet.h) = "signed" for level sets that do not carry it already. Unnamed level
/// sets are named "surface"
/// ("surface_2", ... if taken), other unnamed grids "grid_<position>".
/// Throws InputError for an empty list, a null grid, a non-standard grid type (only OpenVDB's
/// standard bool, mask, float, double, int32, int64, Vec3s, Vec3d and Vec3i grids are accepted)
/// or duplicate grid names; RuntimeFailure when the file cannot be written.
void writeVdb(const std::filesystem::path& path, const openvdb::GridPtrVec& grids,
              const VdbWriteOptions& options = {});

/// Summary of one grid in a .vdb file, for `d2vdb info`.
struct VdbGridInfo {
  std::string name;
  std::string valueType;                    ///< e.g. "float", "vec3s"
  std::string gridClass;                    ///< "level set", "fog volume", "staggered", "unknown"
  openvdb::Vec3d voxelSize{0.0, 0.0, 0.0};  ///< world units per voxel along each axis
  std::uint64_t activeVoxelCount = 0;
  openvdb::CoordBBox indexBoundingBox;  ///< of the active voxels (index space); empty if none
  openvdb::BBoxd worldBoundingBox;      ///< of the active voxel centres (world space)
  std::uint64_t memoryBytes = 0;        ///< in-memory size of the grid once loaded
  std::vector<std::pair<std::string, std::string>> metadata;  ///< name, value as text
};

/// Reads `path` like readAllGrids() and summarises each grid, in file order.
std::vector<VdbGridInfo> describeVdbFile(const std::filesystem::path& path);

/// Summarises each grid of `grids` (e.g. from readAllGrids()), in order; null entries are skipped.
/// Never throws (beyond std::bad_alloc).
std::vector<VdbGridInfo> summarizeGrids(const std::vector<openvdb::GridBase::Ptr>& grids);

}  // namespace d2vdb
