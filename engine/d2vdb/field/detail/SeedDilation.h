// Internal: the dilation that turns the voxels containing seed points into the candidate voxels
// of a band found from seeds (FieldBand::nearSeeds).
#pragma once

#include <array>
#include <cstdint>

namespace d2vdb::detail {

/// A dilation of a set of voxels by `cubeSteps` 26-neighbour steps and then `diamondSteps`
/// 6-neighbour steps: it adds to each voxel the integer offsets w of the Minkowski sum of the cube
/// max_i |w_i| <= cubeSteps and the octahedron sum_i |w_i| <= diamondSteps, i.e. the offsets with
/// sum_i max(|w_i| - cubeSteps, 0) <= diamondSteps.
struct SeedDilation {
  int cubeSteps = 0;
  int diamondSteps = 0;

  /// Whether the dilation adds offset w.
  bool contains(const std::array<int, 3>& w) const;
  /// The number of offsets it adds (the voxel itself included).
  std::int64_t offsetCount() const;
};

/// Whether a voxel centre at integer offset w from the voxel containing a point p can lie
/// within `radius` voxels of p: the distance from w to the cube [-1/2, 1/2]^3 (where p lies
/// relative to its voxel's centre, in voxels) is below `radius`, i.e.
/// sum_i max(|w_i| - 1/2, 0)^2 < radius^2.
bool withinRadiusOfVoxel(const std::array<int, 3>& w, double radius);

/// The smallest dilation (fewest offsets; of those, the fewest steps) whose offsets include every
/// w with withinRadiusOfVoxel(w, radius): dilating the voxels that contain a set of points then
/// yields every voxel whose centre lies within `radius` voxels of one of the points. Found by
/// checking every (cubeSteps, diamondSteps) with at most as many steps as the 26-neighbour steps
/// alone need (ceil(radius - 1/2), which always suffices). Throws InputError unless
/// 0 < radius <= 200 (voxels).
SeedDilation seedDilation(double radius);

}  // namespace d2vdb::detail
