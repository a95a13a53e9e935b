// Level sets from density (fog-volume) grids: the iso-surface of a density rebuilt as a narrow-band
// signed distance field, for inputs from tools that store shapes as densities.
#pragma once

#include <openvdb/openvdb.h>

namespace d2vdb {

/// Whether `grid` holds a density rather than signed distances: its class is GRID_FOG_VOLUME, or
/// its class is unknown, its background is 0 and none of its active values is negative (signed
/// distances are negative inside). Never throws.
bool holdsDensity(const openvdb::FloatGrid& grid);

/// The narrow-band level set (class level set, same transform, `halfWidth` voxels on each side)
/// of the iso-surface {value = iso} of `grid`, negative where the value exceeds `iso` for a
/// density (holdsDensity()) and where it is below `iso` for signed distances. Built by OpenVDB's
/// levelSetRebuild (the iso-surface meshed by volumeToMesh, then meshToVolume, whose signs come
/// from a flood fill of the exterior): distances to the meshed iso-surface, exact to about a
/// tenth of a voxel within two voxels of it, approximate (up to about half a voxel) in the
/// band's outermost layer, which meshToVolume fills by a sweep. Throws InputError when `iso` is not
/// finite, `halfWidth` is below 1, or no value of the grid lies on both sides of `iso` (no surface
/// there), naming the values the grid spans.
openvdb::FloatGrid::Ptr levelSetOfIsoSurface(const openvdb::FloatGrid& grid, double iso,
                                             double halfWidth = 3.0);

}  // namespace d2vdb
