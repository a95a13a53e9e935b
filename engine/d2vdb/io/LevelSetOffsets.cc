#include "d2vdb/io/LevelSetOffsets.h"

#include <openvdb/tools/LevelSetFilter.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {

OffsetLevelSet loadOffsetLevelSet(const std::filesystem::path& path, const LevelSetOptions& options,
                                  const ProgressCallback& progress) {
  LoadOptions load;
  load.purpose = "the input of 'd2vdb offset --method levelset' (a closed mesh or a level set)";
  LoadedInput loaded = loadInput(path, {InputKind::Mesh, InputKind::LevelSet}, load);
  OffsetLevelSet input;
  input.kind = loaded.kind();
  if (loaded.kind() == InputKind::LevelSet) {
    input.grid = std::move(loaded).take<LevelSetInput>().floatGrid();
    if (input.grid->getGridClass() != openvdb::GRID_LEVEL_SET) {
      throw InputError(
          "grid '" + input.grid->getName() + "' of '" + path.string() +
          "' is not a level set (its class is '" +
          openvdb::GridBase::gridClassToString(input.grid->getGridClass()) +
          "'; an unsigned distance, such as a curve's or a point set's field, or a density): the "
          "level-set method offsets the signed distance of a closed surface");
    }
    return input;
  }
  const TriangleMesh mesh = std::move(loaded).take<MeshInput>().mesh;
  if (mesh.triangles.empty()) {
    throw InputError("'" + path.string() +
                     "' has no triangles: the level-set method needs a closed mesh or a level "
                     "set");
  }
  LevelSetResult result = meshToLevelSet(mesh, options, progress);
  input.grid = result.grid;
  input.warnings = std::move(result.warnings);
  return input;
}

void checkLevelSetOffsetBudget(const openvdb::FloatGrid& levelSet,
                               const std::vector<double>& distances, double halfWidth,
                               std::uint64_t maxActiveVoxels) {
  const double voxel = levelSet.voxelSize()[0];
  const openvdb::CoordBBox indexBox = levelSet.evalActiveVoxelBoundingBox();
  const openvdb::Vec3d size = indexBox.dim().asVec3d() * voxel;
  for (const double d : distances) {
    const double grow = std::max(0.0, 2.0 * d);
    const double sx = size.x() + grow, sy = size.y() + grow, sz = size.z() + grow;
    const double area = 2.0 * (sx * sy + sy * sz + sz * sx);
    const double estimate = area / (voxel * voxel) * 2.0 * halfWidth * 1.25;
    if (estimate > static_cast<double>(maxActiveVoxels)) {
      throw InputError("offsetting by " + formatNumber(d, 6) + " at voxel size " +
                       formatNumber(voxel, 6) + " would need about " +
                       std::to_string(static_cast<long long>(estimate)) +
                       " active voxels, above --max-voxels " + std::to_string(maxActiveVoxels) +
                       "; use a larger --voxel-size");
    }
    const double steps = std::ceil(2.0 * std::abs(d) / voxel);
    const double updates = steps * estimate;
    if (updates > kMaxLevelSetOffsetUpdates) {
      throw InputError(
          "offsetting by " + formatNumber(d, 6) + " at voxel size " + formatNumber(voxel, 6) +
          " moves the band in " + std::to_string(static_cast<long long>(steps)) +
          " half-voxel steps over up to " + std::to_string(static_cast<long long>(estimate)) +
          " voxels: about " + formatNumber(updates, 3) + " voxel updates, above the " +
          formatNumber(kMaxLevelSetOffsetUpdates, 3) +
          " (about a minute) the level-set method is allowed; use --method support "
          "(exact offsets at any distance), a larger --voxel-size, or a smaller "
          "distance");
    }
  }
}

LevelSetOffset offsetLevelSet(const openvdb::FloatGrid& levelSet, double distance,
                              const std::string& source, const ProgressCallback& progress) {
  LevelSetOffset offset;
  offset.grid = levelSet.deepCopy();
  openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*offset.grid);
  filter.offset(static_cast<float>(-distance));  // OpenVDB adds its argument to the distances
  const IsoSurfaceOptions iso;
  offset.mesh = extractIsoSurface(*offset.grid, iso, progress);
  if (offset.mesh.triangles.empty()) {
    throw InputError("the offset at distance " + formatNumber(distance, 6) + " of '" + source +
                     "' is empty (the body is thinner than 2 |d|)");
  }
  return offset;
}

}  // namespace d2vdb
