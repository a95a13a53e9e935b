// Exact inside/outside signs for the narrow band of a mesh level set built by OpenVDB.
#pragma once

#include <openvdb/openvdb.h>

#include <cstddef>
#include <functional>

#include "d2vdb/field/detail/InsideOutsideMesh.h"
#include "d2vdb/field/detail/WindingNumber.h"

namespace d2vdb::detail {

/// How each band voxel's side is decided.
enum class BandSignMode {
  /// Watertight mesh without self-intersections: the closest-feature pseudonormal test near the
  /// surface, one winding number per edge-connected component for the absolute side, and
  /// certified propagation through the rest of the band.
  closestFeature,
  /// Watertight mesh that intersects itself: a winding number for every voxel near the surface,
  /// propagation through the rest of the band.
  windingNumberNearSurface,
  /// Not watertight (holes, unbalanced non-manifold edges): a winding number for every voxel.
  windingNumberEveryVoxel,
};

/// What correctBandSigns() found and changed.
struct BandSignReport {
  std::size_t correctedVoxels = 0;       ///< active voxels whose sign was flipped
  std::size_t windingNumberQueries = 0;  ///< points at which the winding number was evaluated
  std::size_t nearVoxels = 0;            ///< within 0.837 voxel of the mesh: decided one by one
  std::size_t farComponents = 0;         ///< connected groups of the other voxels
  std::size_t conflicts = 0;  ///< groups whose neighbours disagreed (then decided per voxel)
};

/// Decides, for every active voxel of `grid` (the level set meshToVolume built, values in world
/// units) whether its centre is inside the mesh (generalised winding number >= 1/2), and flips
/// the voxels whose sign disagrees. `closest` is meshToVolume's closest-triangle grid; `mesh` and
/// `winding` hold the same triangles in index space (voxel units), repaired winding.
///
/// Why it is exact. OpenVDB's voxelisation computes, for every voxel within sqrt(3)/2 voxel of a
/// triangle, the distance to that triangle, and keeps the smallest: a voxel whose distance d to
/// the mesh is below 0.837 voxel (< sqrt(0.7)) therefore has its true closest triangle in
/// `closest` (up to float ties), and a voxel where the distance to the recorded triangle exceeds
/// it is farther than 0.836 voxel from the mesh. Near voxels are decided one by one (closest-
/// feature test or winding number). Two neighbouring voxels whose balls of those radii overlap
/// (d1 + d2 > 1 voxel) see no surface between them and share their side; the far voxels form
/// groups so linked, and each group takes the side of a linked near voxel, or one winding number
/// when it has none (the winding number is constant between surfaces of a watertight mesh). A
/// group whose near neighbours disagree (impossible in exact arithmetic) is decided voxel by voxel.
///
/// A flipped voxel and its 26 neighbours get +-(distance to their recorded closest triangle)
/// (OpenVDB had renormalised their values with the wrong sign nearby); voxels within 1e-6 voxel
/// of the mesh keep OpenVDB's sign. When anything flipped, the signs of the inactive values and
/// tiles are flood-filled again from the band. Deterministic for any thread count.
BandSignReport correctBandSigns(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closest,
                                const InsideOutsideMesh& mesh, const WindingNumberField& winding,
                                BandSignMode mode);

}  // namespace d2vdb::detail
