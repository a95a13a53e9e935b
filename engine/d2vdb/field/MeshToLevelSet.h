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
  /// Signed fields: decide every band voxel's side exactly (see meshToLevelSet()). false keeps the
  /// signs of OpenVDB's exterior sweep, which can be wrong next to sharp concave corners and
  /// across holes, but costs nothing extra.
  bool exactSigns = true;
  std::uint64_t maxActiveVoxels = kDefaultMaxActiveVoxels;  ///< see VoxelBudget.h
  /// Refuse conversions whose estimated peak memory exceeds this many bytes (0 = no limit): per
  /// estimated active voxel kLevelSetPeakBytesPerVoxel plus extraBytesPerVoxel, plus
  /// kLevelSetBytesPerTriangle per triangle (VoxelBudget.h).
  std::uint64_t maxMemoryBytes = kDefaultMaxMemoryBytes;
  /// Memory per voxel of what the caller builds on the level set while it is alive (e.g.
  /// kApproximantBytesPerVoxel for a field), counted against maxMemoryBytes.
  double extraBytesPerVoxel = 0;
};

/// How meshToLevelSet() decided inside and outside.
enum class SignMethod {
  none,  ///< unsigned distance, or exactSigns off (OpenVDB's exterior sweep, unchecked)
  /// The mesh (with its holes closed) does not intersect itself: near the surface, the side of
  /// each voxel's closest point (angle-weighted pseudonormal); the fast path.
  closestFeature,
  /// The mesh intersects or touches itself: a winding number at every voxel near the surface.
  windingNumber,
};

/// Name of a SignMethod as the CLI prints it: "closest feature", "winding number", "none".
const char* signMethodName(SignMethod method);

/// What the exact-sign pass of meshToLevelSet() did.
struct SignReport {
  SignMethod method = SignMethod::none;
  /// Band voxels whose sign from OpenVDB's conversion disagreed with the exact decision and was
  /// flipped.
  std::size_t correctedVoxels = 0;
  std::size_t windingNumberQueries = 0;  ///< points where a winding number was evaluated
  std::size_t reorientedTriangles = 0;   ///< triangles wound against their neighbours, reversed
  bool watertight = false;        ///< every edge crossed equally often both ways (after repair)
  std::size_t holesClosed = 0;    ///< boundary loops closed by a virtual cap (not watertight)
  bool selfIntersecting = false;  ///< the mesh, holes closed, intersects or touches itself
  /// Pockets given the side around them: regions of one side enclosed by the other within the
  /// band next to open or non-manifold parts of the mesh (see meshToLevelSet()).
  std::size_t pocketsFilled = 0;
  std::size_t pocketVoxels = 0;  ///< their voxels
  /// Voxels activated beyond the band beside the surfaces that close holes (see meshToLevelSet()).
  std::size_t holeVoxels = 0;
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
  SignReport signs;                   ///< how inside/outside was decided (signed fields)
  std::vector<std::string> warnings;  ///< one sentence each, e.g. "the mesh is not closed ..."
};

/// Converts a triangle mesh (world units) to a narrow-band distance field with
/// openvdb::tools::meshToVolume, then (signed fields, exactSigns) checks every band voxel's sign
/// and flips the wrong ones.
///
/// Inside is where the generalised winding number of the mesh is at least 1/2 (Jacobson, Kavan,
/// Sorkine-Hornung 2013): for a closed mesh, the exact inside of the solid it bounds; for a mesh
/// with holes, a smooth closing of the holes. Triangles wound against their neighbours are
/// reversed first (each edge-connected part keeps the winding of most of its area; an inside-out
/// mesh is turned right side out). OpenVDB's sign comes from an exterior sweep and a local test
/// that errs next to sharp concave corners (isolated voxels of the wrong sign) and across holes.
/// The check: near the surface (within sqrt(0.7) voxel) each voxel is decided by the
/// angle-weighted pseudonormal of its exact closest point (Baerentzen and Aanaes 2005) when the
/// mesh is watertight and does not intersect itself, else by its winding number (Barill et al.
/// 2018 evaluation, with a certified error bound); the rest of the band takes the side of
/// certified neighbours, with one winding number per group that has none (for meshes with holes:
/// one per voxel). Flipped voxels and their neighbours get the distance to their closest
/// triangle with the new sign, and inactive values are flood-filled again. `signs` reports the
/// method and the number of corrected voxels (a report, not a warning: correcting them is the
/// check's job); holes and self-intersections produce warnings.
///
/// Two rules make the sign field of an open or non-manifold mesh mesh as closed surfaces (both
/// leave closed 2-manifold meshes untouched):
/// - Holes: where the surface w = 1/2 that closes a hole leaves the band, the voxels on both of
///   its sides are activated (decided exactly, with the band's largest magnitude, so marching
///   cubes puts the closing within half a voxel of w = 1/2), and the inactive values around them
///   take their exact sides (detail::coverHoleCrossings()); `signs.holeVoxels` counts them.
/// - Pockets: a region of one side enclosed by the other within the band (thinner than the band)
///   next to a part of the mesh that is not a closed 2-manifold (a flap, a sheet meeting the body
///   at non-manifold edges, a hole) or that meets another part (a fold that turns a scan's
///   surface inside out) takes the side around it when it is outside (a cavity the
///   winding number leaves beside junk inside a solid), or when it is inside and at most 8 voxels
///   (a speck). Cavities bounded by closed 2-manifold shells that touch nothing else stay
///   (detail::fillSignPockets()); `signs.pocketsFilled` and `signs.pocketVoxels` count them.
///
/// Without exact signs, the sign does not depend on triangle orientation and holes a few voxels
/// across are bridged by the voxels the surrounding triangles touch; wider holes let the outside
/// in. A mesh that is not closed produces a warning, and a signed field with no inside voxel
/// another one.
/// Values: where |d| < 1 voxel, the exact distance to the mesh; further out OpenVDB extends the
/// band from neighbouring voxels' closest triangles and the band is renormalised (the README
/// gives the measured accuracy).
/// Deterministic: the same input gives a bitwise-identical grid for any thread count.
/// `progress` receives stage "mesh to level set" with fractions 0..1 (OpenVDB's conversion, whose
/// last fraction is repeated every 0.1 s between its seldom reports, possibly from a worker
/// thread, never concurrently), then with exact signs stage "exact signs (closest feature)" or
/// "exact signs (winding number)" with fractions 0..1, from the calling thread.
/// Throws InputError for an empty mesh, out-of-range indices, non-finite coordinates, a bounding
/// box of zero extent, a missing or non-positive voxel size/resolution, halfWidth < 1, an index
/// range beyond +-2^30, or an estimated active voxel count above maxActiveVoxels (checked before
/// any grid is allocated).
LevelSetResult meshToLevelSet(const TriangleMesh& mesh, const LevelSetOptions& options,
                              const ProgressCallback& progress = {});

}  // namespace d2vdb
