// Offsets of a closed surface the level-set way, the reference for support-function offsets: the
// level set of the input (a .vdb, or a closed mesh converted), moved by OpenVDB's
// LevelSetFilter::offset (in steps of at most half a voxel, renormalised after each), and its zero
// iso-surface by marching cubes:
//
//   const d2vdb::OffsetLevelSet input = d2vdb::loadOffsetLevelSet("bunny.vdb", {});
//   const d2vdb::LevelSetOffset offset = d2vdb::offsetLevelSet(*input.grid, 0.01, "bunny.vdb");
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// The level set offsetLevelSet() moves, with where it came from.
struct OffsetLevelSet {
  openvdb::FloatGrid::Ptr grid;
  InputKind kind = InputKind::LevelSet;  ///< LevelSet (the file's own), or Mesh (converted)
  std::vector<std::string> warnings;     ///< meshToLevelSet()'s, for a mesh
};

/// Loads `path` as a level set (.vdb; selectGrid()'s float grid) or converts a mesh with triangles
/// by meshToLevelSet() with `options` (`progress` follows the conversion). Throws InputError for
/// other kinds, a grid whose class is not level set (unsigned distances of curve and point
/// fields, densities), a mesh without triangles, and as loadInput() and meshToLevelSet() do.
OffsetLevelSet loadOffsetLevelSet(const std::filesystem::path& path, const LevelSetOptions& options,
                                  const ProgressCallback& progress = {});

/// The most voxel updates checkLevelSetOffsetBudget() lets one offset make: OpenVDB's
/// LevelSetFilter::offset moves the band half a voxel per step and updates and renormalises every
/// band voxel at each, about 12-15 million updates per second on two cores here (an ellipsoid
/// offset by 2, 4 and 8 at voxel 0.083: 1.8, 6.6 and 31 s), so this is about a minute.
inline constexpr double kMaxLevelSetOffsetUpdates = 1e9;

/// Throws InputError when offsetting `levelSet` by one of `distances` could need more than
/// `maxActiveVoxels` active voxels, or more than kMaxLevelSetOffsetUpdates voxel updates. The
/// band keeps its width (`halfWidth` voxels on each side) while it moves, so an outward offset
/// grows it with the surface: the estimate bounds the offset surface's area by that of the active
/// voxels' bounding box grown by d on every side; the updates are that many voxels times the
/// 2 |d| / voxel steps.
void checkLevelSetOffsetBudget(const openvdb::FloatGrid& levelSet,
                               const std::vector<double>& distances, double halfWidth,
                               std::uint64_t maxActiveVoxels);

/// An offset level set and its zero iso-surface.
struct LevelSetOffset {
  openvdb::FloatGrid::Ptr grid;  ///< a copy of the input, offset
  TriangleMesh mesh;             ///< extractIsoSurface() of `grid` (with normals)
};

/// `levelSet` offset by the signed distance `distance` (outward for d > 0) and its iso-surface
/// (`progress` follows the marching cubes). Throws InputError (naming `source`, the input) when
/// the offset is empty (the body is thinner than 2 |d|), and as extractIsoSurface() does.
LevelSetOffset offsetLevelSet(const openvdb::FloatGrid& levelSet, double distance,
                              const std::string& source, const ProgressCallback& progress = {});

}  // namespace d2vdb
