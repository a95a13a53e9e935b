// Estimating the size of a narrow-band level set before building it, and refusing requests that
// would exhaust memory.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "d2vdb/core/ResourceBudget.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// Default limit on the active voxels of one level set, sized for a 24 GiB machine: the mesh
/// conversion's peak memory per active voxel and the approximant grids that later share the level
/// set's topology must fit beside each other (the measured figures are in the README, "mesh2sdf").
inline constexpr std::uint64_t kDefaultMaxActiveVoxels = 150'000'000;

/// Default resolution of a narrow band built from a target without a voxel size: voxels along the
/// longest side of the target's bounding box (every front end uses this one value).
inline constexpr int kDefaultResolution = 256;

/// The voxel edge length (world units) of a band around a target whose bounding box is
/// `longestSide` long on its longest side: `voxelSize` when positive, else longestSide /
/// resolution. Throws InputError when no voxel size is given and the box has zero extent (or is
/// empty or not finite), naming `what` ("mesh", "point set", "curve", ...), and when resolution is
/// not positive.
double voxelSizeForBox(double longestSide, double voxelSize, int resolution,
                       const std::string& what);

/// The smallest voxel edge (world units) an OpenVDB grid can have: its linear transforms refuse
/// a voxel volume below 3e-15 ("Non-zero scale values required"), an edge of 1.4422e-5; rounded
/// up. Geometry smaller than a few of these must be expressed in smaller units (millimetres, not
/// metres) to be resolved.
inline constexpr double kMinimumVoxelSize = 1.5e-5;

/// The largest |index coordinate| a level set may reach: well inside OpenVDB's 32-bit range.
inline constexpr double kMaxIndexCoordinate = 1 << 30;

/// Throws InputError, naming `subject` (e.g. "the level set of sphere(...)"), unless
/// `voxelSize` is finite and at least kMinimumVoxelSize; the message gives the voxel size, the
/// limit and the remedy (larger voxels, or the geometry in smaller units).
void checkVoxelSizeIsRepresentable(double voxelSize, const std::string& subject);

/// Factor applied to the band volume estimate below: voxel centres of a band of width 2r fill
/// slightly more than its volume (OpenVDB's mesh band can be a fraction of a voxel wider than
/// asked), and sharp features add wedges the per-piece box terms only approximate.
inline constexpr double kActiveVoxelSafetyFactor = 1.25;

/// One connected piece of a surface: its area (world units squared) and the side lengths of its
/// axis-aligned bounding box (world units).
struct SurfacePiece {
  double area = 0.0;
  std::array<double, 3> boxSides{0.0, 0.0, 0.0};
};

/// The connected pieces (triangles sharing a vertex) of `mesh`, with their areas and boxes.
/// Indices must be in range (validateMesh's contract). O(V + F).
std::vector<SurfacePiece> surfacePieces(const TriangleMesh& mesh);

/// What a level-set builder is about to allocate; see enforceVoxelBudget().
struct VoxelBudgetRequest {
  std::string subject;     ///< what is converted, for the message, e.g. "mesh (12 triangles)"
  double surfaceArea = 0;  ///< world units squared (used when `pieces` is empty)
  /// Bounding box of the whole surface (world); all zero = unknown (no box bound).
  std::array<double, 3> boxSides{0.0, 0.0, 0.0};
  /// The surface's connected pieces; empty = one piece of `surfaceArea` in `boxSides`.
  std::vector<SurfacePiece> pieces;
  double voxelSize = 0;    ///< world units
  double halfWidth = 3;    ///< voxels on each side of the surface
  double longestSide = 0;  ///< longest bounding-box side (world); 0 = unknown (no resolution hint)
  std::uint64_t maxActiveVoxels = kDefaultMaxActiveVoxels;
  /// Peak memory per active voxel of what is built on the band (kLevelSetPeakBytesPerVoxel for a
  /// level set, plus kApproximantBytesPerVoxel for a field); 0 = no memory check.
  double bytesPerVoxel = 0;
  /// Memory besides the voxels (e.g. the conversion's per-triangle structures), bytes.
  double fixedBytes = 0;
  /// The memory budget (core/ResourceBudget.h); 0 = no limit.
  std::uint64_t maxMemoryBytes = kDefaultMaxMemoryBytes;
};

/// Peak memory of converting a mesh to a level set, bytes per active voxel: measured 37 (README,
/// "mesh2sdf": peak-RSS increase during meshToLevelSet of an 81,920-triangle icosphere, 7.5e5 to
/// 4.8e7 voxels), rounded up.
inline constexpr double kLevelSetPeakBytesPerVoxel = 40.0;

/// Memory of the approximant grids that share a level set's topology (ApproximantField.h), bytes
/// per band voxel: measured about 96 (README, "mesh2sdf"), plus the level set's own 12, rounded
/// up.
inline constexpr double kApproximantBytesPerVoxel = 110.0;

/// Peak memory of OpenVDB's mesh conversion per input triangle, bytes (its polygon copy, the
/// closest-triangle index grids and the exact-sign pass's bounding-volume tree): measured about
/// 200 ('d2vdb offset' of a support function at --subdivisions 7 to a .vdb, 327,680 triangles),
/// rounded up.
inline constexpr double kLevelSetBytesPerTriangle = 250.0;

/// Estimated active voxel count of the request's band: the volume within r = halfWidth *
/// voxelSize of the surface, over voxelSize^3, times kActiveVoxelSafetyFactor. A piece of area A
/// whose box B has volume V_B, area A_B and mean width term M_B = pi (a + b + c) contributes
///   min(2 A r + M_B r^2 + 4/3 pi r^3,  V_B + A_B g + M_B g^2 + 4/3 pi g^3),  g = r + voxelSize /
///   2;
/// the first is the band of a flat sheet with the edge and corner terms of Steiner's formula for
/// B, the second is Steiner's formula itself: the volume of B grown by g, which holds the voxel
/// centres of the piece's band (a slab of width w holds up to w / voxelSize + 1 layers of them),
/// and which takes over once the band fills the box. The sum over pieces is capped by the same
/// bound for the whole surface's box. A double because absurd requests exceed 2^64; +inf for
/// a non-positive voxel size.
double estimateActiveVoxels(const VoxelBudgetRequest& request);

/// The smallest voxel size (world units) whose estimate stays within request.maxActiveVoxels, or
/// +inf when none does: as the voxel size grows the estimate falls towards
/// minimumActiveVoxels(halfWidth), a ball of halfWidth voxels.
double smallestVoxelSizeWithinBudget(const VoxelBudgetRequest& request);

/// The estimate's limit for large voxels, whatever the surface: kActiveVoxelSafetyFactor * 4/3 pi
/// halfWidth^3.
double minimumActiveVoxels(double halfWidth);

/// The band's estimated memory: request.fixedBytes + request.bytesPerVoxel *
/// estimateActiveVoxels(request).
double estimateBandMemoryBytes(const VoxelBudgetRequest& request);

/// Throws InputError when the estimate exceeds the voxel limit or, with request.bytesPerVoxel
/// set, its memory (estimateBandMemoryBytes()) exceeds request.maxMemoryBytes (the message then
/// names --max-memory), or, within both, request.voxelSize is not
/// representable (checkVoxelSizeIsRepresentable()), before anything is allocated. The
/// message states the estimate, the limit, and the smallest voxel size (and, when the longest side
/// is known, the largest resolution along it) that would fit, or, when no voxel size fits, the
/// largest half-width that would.
void enforceVoxelBudget(const VoxelBudgetRequest& request);

}  // namespace d2vdb
