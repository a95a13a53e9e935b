// Exact inside/outside signs for the narrow band of a mesh level set built by OpenVDB.
#pragma once

#include <openvdb/openvdb.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "d2vdb/field/detail/InsideOutsideMesh.h"
#include "d2vdb/field/detail/WindingNumber.h"

namespace d2vdb::detail {

/// The integer winding number W of M + S just in front of and just behind one edge-connected
/// component, valid along the whole component when M + S is embedded.
struct ComponentSides {
  std::int16_t front = 0;
  std::int16_t back = 0;
  bool known = false;  ///< false for a component of degenerate triangles only
  /// Another part of the mesh winds around it (a nested shell or a cavity's wall).
  bool enclosed = false;
};

/// Front and back W of every component of an embedded M + S: at the centroid of its largest
/// face, the certified winding number of everything but that face, -+ 1/2 (W jumps by -1 across
/// a face along its normal). One evaluation per component, in parallel.
std::vector<ComponentSides> componentSides(const InsideOutsideMesh& mesh,
                                           const WindingNumberField& closed);

/// What correctBandSigns() works from.
struct BandSignInputs {
  const InsideOutsideMesh* mesh = nullptr;     ///< index space (voxel units), M + S
  const WindingNumberField* closed = nullptr;  ///< over mesh->triangles (M + S)
  const WindingNumberField* caps = nullptr;    ///< over mesh->caps (S); null without caps
  /// M + S does not intersect itself: near voxels are decided by the closest-feature test with
  /// `sides`; otherwise by a winding number each.
  bool embedded = false;
  const std::vector<ComponentSides>* sides = nullptr;
  /// Receives fractions 0..1 of the pass as its phases finish, from the calling thread; may be
  /// empty.
  std::function<void(double)> progress;
};

/// What correctBandSigns() found and changed.
struct BandSignReport {
  std::size_t correctedVoxels = 0;       ///< active voxels whose sign was flipped
  std::size_t windingNumberQueries = 0;  ///< points where W (of M + S) was evaluated
  std::size_t capQueries = 0;            ///< points where the caps' w_S was evaluated
  std::size_t nearVoxels = 0;            ///< within sqrt(0.7) voxel of M + S: decided one by one
  std::size_t farComponents = 0;         ///< connected groups of the other voxels
  std::size_t conflicts = 0;  ///< groups whose neighbours disagreed (then decided per voxel)
};

/// Decides, for every active voxel of `grid` (the level set meshToVolume built without its
/// renormalisation and trimming, so that values are distances to actual triangles; world units),
/// whether its centre is inside the mesh M (generalised winding number w >= 1/2), and flips the
/// voxels whose sign disagrees. `closest` is meshToVolume's closest-triangle grid (indices of M's
/// triangles). With W the integer winding number of M + S and w_S the caps', inside means
/// W - w_S >= 1/2.
///
/// Why it is exact. OpenVDB's voxelisation computes, for every voxel within sqrt(3)/2 voxel of a
/// triangle, the distance to that triangle, and keeps the smallest: a voxel whose distance to M
/// is below 0.837 voxel (sqrt(0.7)) therefore has its true closest triangle of M in `closest` (up
/// to float ties), and a voxel farther from that recorded triangle is more than 0.836 voxel from
/// M. Distances to the caps are computed exactly. A voxel within sqrt(0.7) voxel of M + S (near)
/// gets W from the side of its closest point -- the sign of (p - closest) . pseudonormal, which
/// for an embedded, watertight surface tells front from back (Baerentzen and Aanaes 2005), and
/// the front and back values of W of each edge-connected component, two winding numbers each --
/// or from its own winding number. Two 6-neighbours whose distance bounds add up to more than a
/// voxel have no surface between them and share W; the other (far) voxels form groups so linked,
/// each taking W from a linked near voxel, or from one winding number when it has none. A group
/// whose near neighbours disagree (impossible in exact arithmetic) is decided voxel by voxel.
/// Winding numbers are certified (WindingNumberField::decide), so every decision is exact up to
/// float ties.
///
/// Flipped voxels change sign; they and the near voxels around them (26-neighbours) take the
/// exact distance to M when they are near it. Voxels within 1e-6 voxel of M keep OpenVDB's sign.
/// When anything flipped, the inactive values and tiles are flood-filled again from the band.
/// Deterministic for any thread count.
BandSignReport correctBandSigns(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closest,
                                const BandSignInputs& inputs);

}  // namespace d2vdb::detail
