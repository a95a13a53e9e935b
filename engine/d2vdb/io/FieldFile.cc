// Field .vdb files (FieldFile.h).
#include "d2vdb/io/FieldFile.h"

namespace d2vdb {

void writeField(const std::filesystem::path& path, const ApproximantField& field,
                const VdbWriteOptions& options) {
  writeVdb(path, fieldToGrids(field), options);
}

ApproximantField readField(const std::filesystem::path& path,
                           const ApproximantFieldOptions& options,
                           const ProgressCallback& progress) {
  return fieldFromGrids(readAllGrids(path), path.string(), options, progress);
}

bool isFieldFile(const std::vector<openvdb::GridBase::Ptr>& grids) {
  // The distance grid: the first level set, else (unsigned distance of curves and points) the
  // first float grid.
  openvdb::GridBase::Ptr distance;
  for (const openvdb::GridBase::Ptr& grid : grids) {
    if (grid && grid->isType<openvdb::FloatGrid>() &&
        grid->getGridClass() == openvdb::GRID_LEVEL_SET) {
      distance = grid;
      break;
    }
  }
  if (!distance) {
    for (const openvdb::GridBase::Ptr& grid : grids) {
      if (grid && grid->isType<openvdb::FloatGrid>()) {
        distance = grid;
        break;
      }
    }
  }
  return distance && static_cast<bool>((*distance)[kFieldKindMetadata]);
}

}  // namespace d2vdb
