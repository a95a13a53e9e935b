// Marching-cubes extraction of an iso-surface from a sparse OpenVDB grid into an indexed mesh.
#pragma once

#include <openvdb/openvdb.h>

#include "d2vdb/core/Progress.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// Parameters of extractIsoSurface().
struct IsoSurfaceOptions {
  /// The iso-value, in the grid's value units (world units for a level set: iso = +r gives the
  /// surface offset outward by r, iso = -r inward). Must be finite.
  double isoValue = 0.0;
  /// Fill TriangleMesh::normals with unit normals from the grid gradient (central differences,
  /// interpolated along the edge), pointing toward increasing values.
  bool computeNormals = true;
  /// Raw output: place every vertex exactly where linear interpolation puts it. By default a
  /// vertex stays at least kCornerClearance voxel from the grid points at the ends of its edge,
  /// so that no triangle has zero area (values equal to the iso-value would otherwise collapse
  /// several vertices onto one grid point); the raw output may contain zero-area triangles but has
  /// the same topology.
  bool raw = false;
};

/// Minimum distance, in voxels, between a vertex and its edge's end points (unless raw).
inline constexpr double kCornerClearance = 0.005;

/// Extracts the surface where the grid's trilinear interpolant crosses options.isoValue.
///
/// Method: marching cubes over the cells (2x2x2 voxel blocks, corners at voxel centres) whose
/// lowest corner lies in an allocated leaf node or in the leaf-sized block just below one along
/// any axes, in parallel over those 8^3 blocks. A corner is inside when its value is below the
/// iso-value. One vertex per crossed edge, placed by linear interpolation and shared by every cell
/// around the edge (also across leaf boundaries); a few cells with 8- to 12-sided contours get one
/// more vertex inside. Ambiguous faces are resolved with the asymptotic decider and cell interiors
/// without tunnels (CubeTables.h), so a closed iso-surface gives a closed, 2-manifold, consistently
/// oriented mesh. Triangles wind counter-clockwise seen from the side of higher values (outward
/// for a level set). Positions are world coordinates (the grid's transform).
///
/// Deterministic: vertices and triangles come in the order of the sorted leaf blocks and, within
/// a block, of the edges and cells, so the output is identical for any thread count.
/// Active tiles are voxelized first (on a copy). No crossing at all gives an empty mesh.
/// `progress` receives stages "contour: counting" and "contour: meshing", from the calling thread.
///
/// Throws InputError for a non-finite iso-value; for a level set (GRID_LEVEL_SET) whose |iso|
/// exceeds the background value minus one voxel (beyond that, vertices would be interpolated from
/// background values instead of distances); and for any grid whose iso-surface leaves the
/// allocated leaf nodes (the mesh would have holes there). The message says by how much the
/// iso-value exceeds the representable range.
TriangleMesh extractIsoSurface(const openvdb::FloatGrid& grid,
                               const IsoSurfaceOptions& options = {},
                               const ProgressCallback& progress = {});

/// Double-precision grids: as above.
TriangleMesh extractIsoSurface(const openvdb::DoubleGrid& grid,
                               const IsoSurfaceOptions& options = {},
                               const ProgressCallback& progress = {});

/// Any grid: dispatches to the float or double version; throws InputError naming the grid and its
/// value type for other value types.
TriangleMesh extractIsoSurface(const openvdb::GridBase& grid, const IsoSurfaceOptions& options = {},
                               const ProgressCallback& progress = {});

}  // namespace d2vdb
