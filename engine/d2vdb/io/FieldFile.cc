// Field .vdb files (FieldFile.h).
#include "d2vdb/io/FieldFile.h"

#include "d2vdb/io/GridSelection.h"

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
  // The distance grid is the grid findGrid() selects: the first float level set (surfaces), else
  // the first float grid (the unsigned distance of curves and points).
  const openvdb::GridBase::Ptr distance = findGrid(grids);
  return distance && static_cast<bool>((*distance)[kFieldKindMetadata]);
}

}  // namespace d2vdb
