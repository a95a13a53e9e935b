// The map between a field's index space (voxel (i, j, k) centred at (i, j, k)) and world space.
#pragma once

#include <openvdb/openvdb.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>

namespace d2vdb::detail {

/// A grid transform that is a rotation, a uniform scale (the voxel size h) and a translation:
/// world = h R index + offset. Immutable; the constructor checks the transform, so every
/// IndexFrame is valid.
class IndexFrame {
 public:
  /// The frame of `transform`. Throws InputError, naming `source`, when the transform is not
  /// linear with cubic voxels, its voxel size is not a positive finite number, or it shears or
  /// mirrors its voxels.
  IndexFrame(const openvdb::math::Transform& transform, const std::string& source);

  /// Voxel size (world units).
  double voxelSize() const { return voxelSize_; }
  /// Whether R is the identity (then direction conversions are exact no-ops).
  bool axisAligned() const { return axisAligned_; }

  Eigen::Vector3d indexToWorld(const Eigen::Vector3d& index) const {
    return indexToWorldLinear_ * index + indexToWorldOffset_;
  }
  Eigen::Vector3d worldToIndex(const Eigen::Vector3d& world) const {
    return worldToIndexLinear_ * (world - indexToWorldOffset_);
  }
  /// Index-frame unit vector to world frame.
  Eigen::Vector3d toWorldDirection(const Eigen::Vector3d& v) const {
    return axisAligned_ ? v : Eigen::Vector3d(rotation_ * v);
  }
  /// World-frame unit vector to index frame.
  Eigen::Vector3d toIndexDirection(const Eigen::Vector3d& v) const {
    return axisAligned_ ? v : Eigen::Vector3d(rotation_.transpose() * v);
  }

 private:
  double voxelSize_ = 0.0;
  Eigen::Matrix3d indexToWorldLinear_ = Eigen::Matrix3d::Identity();  ///< h R
  Eigen::Vector3d indexToWorldOffset_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d worldToIndexLinear_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d rotation_ = Eigen::Matrix3d::Identity();  ///< index frame to world frame
  bool axisAligned_ = true;
};

}  // namespace d2vdb::detail
