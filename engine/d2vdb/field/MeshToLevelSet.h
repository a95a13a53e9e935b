// Narrow-band distance fields of triangle meshes (OpenVDB's mesh-to-volume conversion).
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/VoxelBudget.h"
#include "d2vdb/mesh/MeshValidation.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// Metadata key set on every grid meshToLevelSet() returns: "signed" or "unsigned".
inline constexpr const char* kDistanceKindMetadata = "d2vdb_distance";

/// Parameters of meshToLevelSet().
struct LevelSetOptions {
  double voxelSize = 0;  ///< world units; 0 = derive from `resolution`
  int resolution = 0;    ///< voxels along the longest bounding-box side, used when voxelSize == 0
  double halfWidth = 3;  ///< narrow-band half-width in voxels, inside and outside; at least 1
  /// Unsigned distance for open surfaces (sheets, scans with large holes): no inside/outside.
  bool unsignedDistance = false;
  std::uint64_t maxActiveVoxels = kDefaultMaxActiveVoxels;  ///< see VoxelBudget.h
};

/// What meshToLevelSet() produced.
struct LevelSetResult {
  /// Signed: class GRID_LEVEL_SET, name "surface", values in world units, d < 0 inside, active
  /// voxels |d| < halfWidth * voxelSize, background halfWidth * voxelSize, inside tiles at
  /// -background. Unsigned: class GRID_UNKNOWN (OpenVDB has no class for unsigned distance),
  /// name "unsigned_distance", values |d| >= 0 in the same band, background halfWidth*voxelSize.
  /// Both carry metadata kDistanceKindMetadata = "signed" / "unsigned". Voxel (i,j,k) is centred
  /// at (i,j,k) * voxelSize.
  openvdb::FloatGrid::Ptr grid;
  MeshReport meshReport;              ///< validateMesh() of the input
  std::vector<std::string> warnings;  ///< one sentence each, e.g. "the mesh is not closed ..."
};

/// Converts a triangle mesh (world units) to a narrow-band distance field with
/// openvdb::tools::meshToVolume. The sign comes from OpenVDB's exterior sweep and does not depend
/// on triangle orientation, so flipped triangles, non-manifold edges and holes up to about 3 voxels
/// across (bridged by the voxels the surrounding triangles touch; measured on a sphere of radius
/// 20 voxels: 3.2-voxel holes keep every sign, 4-voxel holes let the outside in) still give a
/// correct sign. A mesh that is not closed produces a warning, and a signed field with no inside
/// voxel (the outside leaked in through a large hole, or the surface is a sheet) another one.
/// Accuracy (measured on a sphere of radius 20 voxels, 5120 triangles): where |d| < 1 voxel the
/// values are the exact distance to the mesh (to 1e-5 voxel); further out OpenVDB extends the
/// band from neighbouring voxels' closest triangles and renormalises, which errs by up to about
/// 0.11 voxel.
/// Deterministic: the same input gives a bitwise-identical grid for any thread count.
/// `progress` receives stage "mesh to level set" with fractions 0..1, from the calling thread.
/// Throws InputError for an empty mesh, out-of-range indices, non-finite coordinates, a bounding
/// box of zero extent, a missing or non-positive voxel size/resolution, halfWidth < 1, an index
/// range beyond +-2^30, or an estimated active voxel count above maxActiveVoxels (checked before
/// any grid is allocated).
LevelSetResult meshToLevelSet(const TriangleMesh& mesh, const LevelSetOptions& options,
                              const ProgressCallback& progress = {});

}  // namespace d2vdb
