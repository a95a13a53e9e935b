// The description of a field's band (FieldBand.h).
#include "d2vdb/field/FieldBand.h"

#include <memory>
#include <utility>

namespace d2vdb {

FieldBand FieldBand::activeVoxelsOf(TargetKind kind, openvdb::FloatGrid::ConstPtr grid) {
  FieldBand band;
  band.kind_ = kind;
  band.grid_ = std::move(grid);
  return band;
}

FieldBand FieldBand::nearSeeds(TargetKind kind, std::vector<Eigen::Vector3d> seeds,
                               double voxelSize, double halfWidth, double seedReach) {
  FieldBand band;
  band.kind_ = kind;
  band.seeds_ = std::move(seeds);
  band.voxelSize_ = voxelSize;
  band.halfWidth_ = halfWidth;
  band.seedReach_ = seedReach;
  return band;
}

FieldBand& FieldBand::setApproximants(VoxelApproximant approximant) {
  // Workers share the one function (a copy per worker could copy what it captures by value).
  auto shared = std::make_shared<const VoxelApproximant>(std::move(approximant));
  factory_ = [shared] {
    return VoxelApproximant([shared](const openvdb::Coord& ijk, const Eigen::Vector3d& center) {
      return (*shared)(ijk, center);
    });
  };
  return *this;
}

FieldBand& FieldBand::setApproximantsPerWorker(VoxelApproximantFactory factory) {
  factory_ = std::move(factory);
  return *this;
}

FieldBand& FieldBand::setEstimator(std::string estimator) {
  estimator_ = std::move(estimator);
  return *this;
}

FieldBand& FieldBand::setLabel(std::string label) {
  label_ = std::move(label);
  return *this;
}

FieldBand& FieldBand::setTargetBounds(const Eigen::AlignedBox3d& bounds) {
  targetBounds_ = bounds;
  return *this;
}

}  // namespace d2vdb
