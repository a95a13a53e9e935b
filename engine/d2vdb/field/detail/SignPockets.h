// Pockets of one side inside the band that only the open or non-manifold parts of a mesh bound.
#pragma once

#include <openvdb/openvdb.h>

#include <cstddef>
#include <vector>

#include "d2vdb/field/detail/InsideOutsideMesh.h"

namespace d2vdb::detail {

/// What fillSignPockets() changed.
struct SignPocketReport {
  std::size_t pockets = 0;  ///< regions given the side around them
  std::size_t voxels = 0;   ///< their voxels
};

/// Per edge-connected component of M + S: whether it is a closed 2-manifold of the input (every
/// edge shared by exactly two of its triangles, none of them a cap).
std::vector<bool> closedComponents(const InsideOutsideMesh& mesh);

/// Largest inside speck (voxels) that fillSignPockets() removes from the outside.
inline constexpr std::size_t kMaxSpeckVoxels = 8;

/// Removes the pockets that the winding-number rule leaves where a scan has junk: curved flaps,
/// doubled sheets and sheets meeting the body at non-manifold edges, holes closed inside the
/// body. With `regions` the connected sets (6-adjacency) of active voxels of one side, a region
/// is a pocket when
/// - it is enclosed by the other side within the band (no voxel of it has an inactive
///   6-neighbour), so it is thinner than the band,
/// - some voxel of it has its closest triangle (`closest`, meshToVolume's closest-triangle grid,
///   indices of M's triangles) on a component that is not a closed 2-manifold, or that meets
///   another component or itself (`intersecting`, per triangle of `mesh`: whether it meets another
///   triangle; a fold that turns a scan's surface inside out is a closed 2-manifold, but the
///   cavity it leaves is junk), and
/// - it is outside (a cavity inside the solid: it lies inside another component), or it is inside
///   and has at most kMaxSpeckVoxels voxels (a speck, e.g. between two nearly coincident sheets,
///   that marching cubes would turn into a shell of about a voxel).
/// A pocket takes the side around it: its values change sign (a value of 0 becomes the smallest
/// normal float of the new sign). Cavities that only closed 2-manifold parts of the input bound
/// and that touch no other part, and regions that reach beyond the band, are kept. Does nothing
/// when every component is a closed 2-manifold and no triangle meets another. Inactive values are
/// left alone (no pocket touches one). Deterministic for any thread count.
SignPocketReport fillSignPockets(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closest,
                                 const InsideOutsideMesh& mesh,
                                 const std::vector<bool>& intersecting);

}  // namespace d2vdb::detail
