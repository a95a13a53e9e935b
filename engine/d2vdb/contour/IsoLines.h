// Marching squares: iso-lines of a grid on an axis-aligned plane, as 2-D polylines.
#pragma once

#include <openvdb/openvdb.h>

#include <Eigen/Core>

#include <array>
#include <vector>

namespace d2vdb {

/// One iso-line on a slice plane, in the plane's world coordinates (u, v) (see Slice).
struct IsoLine {
  std::vector<Eigen::Vector2d> points;  ///< a closed line does not repeat its first point
  bool closed = false;  ///< false only where the line leaves the grid's allocated leaf nodes
};

/// Parameters of sliceIsoLines().
struct SliceOptions {
  int axis = 2;           ///< normal of the plane: 0 = x, 1 = y, 2 = z
  double offset = 0.0;    ///< world coordinate of the plane along `axis` (any value)
  double isoValue = 0.0;  ///< in the grid's value units; must be finite
};

/// The iso-lines of one plane. The plane coordinates are the world coordinates along
/// planeAxes = the two other axes in cyclic order (x: (y, z), y: (z, x), z: (x, y)), so that
/// (u, v, normal) is right-handed. Closed lines run counter-clockwise around the regions below
/// the iso-value (inside a level set) seen from the +normal side, i.e. with the inside on the left.
struct Slice {
  int axis = 2;
  double offset = 0.0;
  std::array<int, 2> planeAxes{0, 1};
  std::vector<IsoLine> lines;
};

/// Marching squares on the plane: values on the plane are interpolated linearly between the two
/// nearest voxel layers (exactly the grid's trilinear interpolant restricted to the plane);
/// vertices by linear interpolation on the cell edges, kept 0.005 voxel from the grid points as in
/// extractIsoSurface(); ambiguous squares resolved by the asymptotic decider (the same rule as the
/// faces in CubeTables.h). Only cells touching an allocated leaf node are visited; lines are
/// chained through shared edge vertices, so a closed level set gives closed lines. Deterministic
/// (serial; the order follows the sorted leaf blocks). Throws InputError for an axis outside 0..2,
/// a non-finite offset or iso-value, or a transform that is not an axis-aligned linear map.
Slice sliceIsoLines(const openvdb::FloatGrid& grid, const SliceOptions& options);

/// Double-precision grids: as above.
Slice sliceIsoLines(const openvdb::DoubleGrid& grid, const SliceOptions& options);

/// Any grid: dispatches to the float or double version; InputError for other value types.
Slice sliceIsoLines(const openvdb::GridBase& grid, const SliceOptions& options);

}  // namespace d2vdb
