// Band voxels on both sides of the surface that closes a mesh's holes, where that surface leaves
// the narrow band.
#pragma once

#include <openvdb/openvdb.h>

#include <cstddef>

#include "d2vdb/field/detail/InsideOutsideMesh.h"
#include "d2vdb/field/detail/WindingNumber.h"

namespace d2vdb::detail {

/// What coverHoleCrossings() added.
struct HoleCrossingReport {
  std::size_t addedVoxels = 0;           ///< voxels activated beside a closing surface
  std::size_t windingNumberQueries = 0;  ///< voxels whose side was evaluated
};

/// Points whose winding number is within this of 1/2 lie on the surface that closes a hole (up
/// to rounding): they count as inside, so that voxel centres on a planar hole's plane all take
/// the same side instead of the rounding's.
inline constexpr double kClosingTie = 1e-9;

/// The side of a voxel centre off M (index space): inside when the winding number of M,
/// W - w_S, is at least 1/2 (less kClosingTie), with W the integer winding number of M + S
/// (signed ray crossings, certified) and w_S the caps' (certified against W - 1/2). A point on
/// a triangle of M + S, where every ray is in doubt, is decided by the exact sums. Thread-safe.
bool insideOfMesh(const InsideOutsideMesh& mesh, const WindingNumberField& closed,
                  const WindingNumberField& caps, const Eigen::Vector3d& point);

/// Makes the inside/outside change of a mesh with holes representable everywhere. Inside is
/// where M's winding number w is at least 1/2, so across a hole the side changes on the smooth
/// surface w = 1/2 that spans it; where that surface lies farther from M than the band reaches,
/// the band's inactive values (flood-filled along scan lines) cannot follow it, and marching cubes
/// would find sign changes outside the stored band (or guess them from the scan order).
///
/// Starting from the voxels just outside the band in the leaves where the caps can matter
/// (|w_S| may reach 1/2), every voxel outside the band that has a 6-neighbour on the other side
/// (decided exactly, insideOfMesh()) is activated, and the search follows these voxels
/// (26-neighbours) along the closing surface until it returns to the band. An activated voxel
/// lies at least the band's half-width from M: it takes the band's largest magnitude
/// (the background rounded toward zero, so the band stays |d| < background) with its side, so
/// marching cubes puts the closing surface halfway between the two voxels around it (within half
/// a voxel of w = 1/2). The inactive voxels of every leaf that received one take +-background by
/// their exact side, and the tiles are flood-filled again from the leaves.
///
/// Does nothing (the grid is untouched) when no such sign change exists. `grid` is a signed level
/// set in index-aligned world units with final signs (after correctBandSigns()); `mesh`, `closed`
/// and `caps` are those of the correction (index space). Deterministic for any thread count.
HoleCrossingReport coverHoleCrossings(openvdb::FloatGrid& grid, const InsideOutsideMesh& mesh,
                                      const WindingNumberField& closed,
                                      const WindingNumberField& caps);

}  // namespace d2vdb::detail
