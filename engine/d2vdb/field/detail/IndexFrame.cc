// Index-to-world maps of a field (IndexFrame.h).
#include "d2vdb/field/detail/IndexFrame.h"

#include <cmath>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {

IndexFrame::IndexFrame(const openvdb::math::Transform& transform, const std::string& source) {
  if (!transform.isLinear() || !transform.hasUniformScale()) {
    throw InputError(source +
                     ": the grid's transform is not a linear map with cubic voxels; "
                     "the approximant field needs uniform voxels (resample it first)");
  }
  const openvdb::Mat4d matrix = transform.baseMap()->getAffineMap()->getMat4();
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      indexToWorldLinear_(column, row) = matrix[row][column];
    }
    indexToWorldOffset_[row] = matrix[3][row];
  }
  voxelSize_ = transform.voxelSize()[0];
  if (!(voxelSize_ > 0.0) || !std::isfinite(voxelSize_)) {
    throw InputError(source + ": the grid's voxel size is not a positive finite number");
  }
  rotation_ = indexToWorldLinear_ / voxelSize_;
  if ((rotation_ * rotation_.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 ||
      rotation_.determinant() < 0.0) {
    throw InputError(source +
                     ": the grid's transform shears or mirrors its voxels; the "
                     "approximant field needs a rotation and uniform scale");
  }
  axisAligned_ = (rotation_ - Eigen::Matrix3d::Identity()).norm() < 1e-12;
  if (axisAligned_) rotation_ = Eigen::Matrix3d::Identity();
  worldToIndexLinear_ = rotation_.transpose() / voxelSize_;
}

}  // namespace d2vdb::detail
