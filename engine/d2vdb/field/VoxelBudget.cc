#include "d2vdb/field/VoxelBudget.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "d2vdb/core/Error.h"

namespace d2vdb {

double estimateActiveVoxels(double surfaceArea, double voxelSize, double halfWidth) {
  if (!(voxelSize > 0.0)) return std::numeric_limits<double>::infinity();
  const double faces = surfaceArea / (voxelSize * voxelSize);
  return faces * 2.0 * halfWidth * kActiveVoxelSafetyFactor;
}

double smallestVoxelSizeWithinBudget(double surfaceArea, double halfWidth,
                                     std::uint64_t maxActiveVoxels) {
  const double limit = static_cast<double>(maxActiveVoxels);
  if (!(limit > 0.0)) return std::numeric_limits<double>::infinity();
  return std::sqrt(surfaceArea * 2.0 * halfWidth * kActiveVoxelSafetyFactor / limit);
}

void enforceVoxelBudget(const VoxelBudgetRequest& request) {
  const double estimate =
      estimateActiveVoxels(request.surfaceArea, request.voxelSize, request.halfWidth);
  if (estimate <= static_cast<double>(request.maxActiveVoxels)) return;

  const double smallestVoxel = smallestVoxelSizeWithinBudget(request.surfaceArea, request.halfWidth,
                                                             request.maxActiveVoxels);
  std::ostringstream message;
  message.precision(3);
  message << request.subject << " at voxel size " << request.voxelSize << " would need about "
          << estimate << " active voxels (surface area " << request.surfaceArea << ", half-width "
          << request.halfWidth << " voxels), above the limit of "
          << static_cast<double>(request.maxActiveVoxels)
          << " active voxels; use a voxel size of at least " << smallestVoxel;
  if (request.longestSide > 0.0 && std::isfinite(smallestVoxel) && smallestVoxel > 0.0) {
    const double largestResolution = std::floor(request.longestSide / smallestVoxel);
    message << " (a resolution of at most " << static_cast<long long>(largestResolution)
            << " voxels along the longest side)";
  }
  message << " or raise the active-voxel limit if the machine has the memory";
  throw InputError(message.str());
}

}  // namespace d2vdb
