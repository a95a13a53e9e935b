#include "d2vdb/field/Primitives.h"

#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/VoxelBudget.h"
#include "d2vdb/field/detail/OpenVdbSetup.h"

namespace d2vdb {

using detail::ensureOpenVdbInitialized;
namespace {

using LeafNode = openvdb::FloatTree::LeafNodeType;
constexpr std::int64_t kLeafDim = LeafNode::DIM;  // voxels along a leaf side (8)

// An inclusive range of leaf blocks; block b covers voxels [8 b, 8 b + 7] on each axis.
struct BlockRange {
  std::array<std::int64_t, 3> lo;
  std::array<std::int64_t, 3> hi;
};

// Floor of numerator / kLeafDim for either sign.
std::int64_t floorDivideByLeafDim(std::int64_t numerator) {
  const std::int64_t quotient = numerator / kLeafDim;
  return (numerator % kLeafDim < 0) ? quotient - 1 : quotient;
}

struct BandGeometry {
  double voxelSize;
  double band;  // halfWidth * voxelSize, world units
};

// Appends to `blocks`, in a fixed depth-first order, the origins of all leaf blocks in `range`
// that may hold a voxel with |d| < band. A box of voxel centres with centre c and half-diagonal h
// holds none if |d(c)| >= band + h, since an exact signed distance is 1-Lipschitz.
void collectCandidateBlocks(const AnalyticShape& shape, const BandGeometry& geometry,
                            const BlockRange& range, std::vector<openvdb::Coord>& blocks) {
  Eigen::Vector3d firstCenter;
  Eigen::Vector3d lastCenter;
  for (int axis = 0; axis < 3; ++axis) {
    firstCenter[axis] = static_cast<double>(range.lo[axis] * kLeafDim) * geometry.voxelSize;
    lastCenter[axis] =
        static_cast<double>(range.hi[axis] * kLeafDim + kLeafDim - 1) * geometry.voxelSize;
  }
  const Eigen::Vector3d center = 0.5 * (firstCenter + lastCenter);
  const double halfDiagonal = 0.5 * (lastCenter - firstCenter).norm();
  // Slack for rounding in the distance evaluation: conservative, it only reduces skipping.
  const double slack =
      1e-9 * (geometry.band + halfDiagonal + center.cwiseAbs().maxCoeff() + geometry.voxelSize);
  if (std::abs(shape.signedDistance(center)) >= geometry.band + halfDiagonal + slack) return;

  int longestAxis = 0;
  std::int64_t longestCount = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const std::int64_t count = range.hi[axis] - range.lo[axis] + 1;
    if (count > longestCount) {
      longestCount = count;
      longestAxis = axis;
    }
  }
  if (longestCount == 1) {
    blocks.emplace_back(static_cast<openvdb::Int32>(range.lo[0] * kLeafDim),
                        static_cast<openvdb::Int32>(range.lo[1] * kLeafDim),
                        static_cast<openvdb::Int32>(range.lo[2] * kLeafDim));
    return;
  }
  const std::int64_t middle = range.lo[longestAxis] + (longestCount - 1) / 2;
  BlockRange lower = range;
  lower.hi[longestAxis] = middle;
  BlockRange upper = range;
  upper.lo[longestAxis] = middle + 1;
  collectCandidateBlocks(shape, geometry, lower, blocks);
  collectCandidateBlocks(shape, geometry, upper, blocks);
}

// Fills the leaf at `origin` with exact distances; returns null when no voxel lies in the band.
std::unique_ptr<LeafNode> makeBandLeaf(const AnalyticShape& shape, const BandGeometry& geometry,
                                       float background, const openvdb::Coord& origin) {
  auto leaf = std::make_unique<LeafNode>(origin, background, /*active=*/false);
  bool anyActive = false;
  for (openvdb::Index offset = 0; offset < LeafNode::SIZE; ++offset) {
    const openvdb::Coord ijk = leaf->offsetToGlobalCoord(offset);
    const Eigen::Vector3d world(static_cast<double>(ijk.x()) * geometry.voxelSize,
                                static_cast<double>(ijk.y()) * geometry.voxelSize,
                                static_cast<double>(ijk.z()) * geometry.voxelSize);
    const double distance = shape.signedDistance(world);
    if (std::abs(distance) < geometry.band) {
      leaf->setValueOn(offset, static_cast<float>(distance));
      anyActive = true;
    } else {
      leaf->setValueOnly(offset, distance < 0.0 ? -background : background);
    }
  }
  if (!anyActive) leaf.reset();
  return leaf;
}

void validateOptions(const AnalyticShape& shape, const PrimitiveLevelSetOptions& options) {
  if (!std::isfinite(options.voxelSize) || !(options.voxelSize > 0.0)) {
    std::ostringstream message;
    message << "level set of " << shape.describe() << ": the voxel size must be a finite positive "
            << "number of world units, got " << options.voxelSize;
    throw InputError(message.str());
  }
  if (!std::isfinite(options.halfWidth) || !(options.halfWidth >= 1.0)) {
    std::ostringstream message;
    message << "level set of " << shape.describe() << ": the narrow-band half-width must be at "
            << "least 1 voxel, got " << options.halfWidth;
    throw InputError(message.str());
  }
}

}  // namespace

openvdb::FloatGrid::Ptr primitiveLevelSet(const AnalyticShape& shape,
                                          const PrimitiveLevelSetOptions& options) {
  validateOptions(shape, options);
  const BandGeometry geometry{options.voxelSize, options.halfWidth * options.voxelSize};

  VoxelBudgetRequest budget;
  budget.subject = "the level set of " + shape.describe();
  budget.surfaceArea = shape.surfaceArea();
  const Eigen::Vector3d sides = shape.bounds().sizes();
  budget.boxSides = {sides.x(), sides.y(), sides.z()};
  budget.voxelSize = options.voxelSize;
  budget.halfWidth = options.halfWidth;
  budget.longestSide = shape.bounds().sizes().maxCoeff();
  budget.maxActiveVoxels = options.maxActiveVoxels;
  budget.bytesPerVoxel = kLevelSetPeakBytesPerVoxel;
  budget.maxMemoryBytes = options.maxMemoryBytes;
  enforceVoxelBudget(budget);

  // Index range of voxel centres that can lie in the band, rounded out to whole leaf blocks.
  const Eigen::AlignedBox3d bounds = shape.bounds();
  BlockRange blocks{};
  for (int axis = 0; axis < 3; ++axis) {
    const double lowIndex = std::floor((bounds.min()[axis] - geometry.band) / geometry.voxelSize);
    const double highIndex = std::ceil((bounds.max()[axis] + geometry.band) / geometry.voxelSize);
    if (!(std::abs(lowIndex) < kMaxIndexCoordinate && std::abs(highIndex) < kMaxIndexCoordinate)) {
      std::ostringstream message;
      message << "the level set of " << shape.describe() << " at voxel size " << options.voxelSize
              << " reaches index coordinate "
              << (std::abs(lowIndex) > std::abs(highIndex) ? lowIndex : highIndex)
              << ", beyond OpenVDB's range of +-2^30; use a larger voxel size or move the shape "
              << "closer to the origin";
      throw InputError(message.str());
    }
    blocks.lo[axis] = floorDivideByLeafDim(static_cast<std::int64_t>(lowIndex));
    blocks.hi[axis] = floorDivideByLeafDim(static_cast<std::int64_t>(highIndex));
  }

  ensureOpenVdbInitialized();
  std::vector<openvdb::Coord> candidateOrigins;
  collectCandidateBlocks(shape, geometry, blocks, candidateOrigins);

  const float background = static_cast<float>(geometry.band);
  std::vector<std::unique_ptr<LeafNode>> leaves(candidateOrigins.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidateOrigins.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        leaves[i] = makeBandLeaf(shape, geometry, background, candidateOrigins[i]);
                      }
                    });

  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(options.voxelSize));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->setName("surface");
  openvdb::FloatTree& tree = grid->tree();
  for (std::unique_ptr<LeafNode>& leaf : leaves) {
    if (leaf) tree.addLeaf(leaf.release());  // the tree takes ownership
  }
  // Leaves already hold exact inactive values; flood only the tiles of the internal nodes.
  openvdb::tools::signedFloodFill(tree, /*threaded=*/true, /*grainSize=*/1, /*minLevel=*/1);
  return grid;
}

}  // namespace d2vdb
