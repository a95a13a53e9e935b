#include "d2vdb/field/detail/BandRenormalization.h"

#include <openvdb/tools/Prune.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace d2vdb::detail {
namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;

void shiftActive(const std::vector<FloatLeaf*>& leaves, float shift) {
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t i) {
    for (auto value = leaves[i]->beginValueOn(); value; ++value) {
      value.setValue(*value + shift);
    }
  });
}

/// Godunov's upwind |grad phi|^2 from one-sided differences (minus = phi - phi(x - h),
/// plus = phi(x + h) - phi), per axis, in value units.
float godunovNorm2(bool outside, const float (&minus)[3], const float (&plus)[3]) {
  float sum = 0.0f;
  for (int axis = 0; axis < 3; ++axis) {
    const float down = outside ? std::max(minus[axis], 0.0f) : std::min(minus[axis], 0.0f);
    const float up = outside ? std::min(plus[axis], 0.0f) : std::max(plus[axis], 0.0f);
    sum += std::max(down * down, up * up);
  }
  return sum;
}

}  // namespace

void renormalizeBand(openvdb::FloatGrid& grid) {
  std::vector<FloatLeaf*> leaves;
  leaves.reserve(grid.tree().leafCount());
  grid.tree().getNodes(leaves);
  if (leaves.empty()) return;
  const float voxel = static_cast<float>(grid.voxelSize()[0]);
  const float inverseVoxel = 1.0f / voxel;
  const float shift = 0.8f * voxel;
  shiftActive(leaves, -shift);
  std::unique_ptr<float[]> stepped(new float[FloatLeaf::SIZE * leaves.size()]);
  const openvdb::FloatTree& tree = grid.tree();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const auto& range) {
    openvdb::tree::ValueAccessor<const openvdb::FloatTree> accessor(tree);
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      float* out = &stepped[i * FloatLeaf::SIZE];
      for (auto value = leaves[i]->cbeginValueOn(); value; ++value) {
        const float phi = *value;
        const openvdb::Coord ijk = value.getCoord();
        const float minus[3] = {phi - accessor.getValue(ijk.offsetBy(-1, 0, 0)),
                                phi - accessor.getValue(ijk.offsetBy(0, -1, 0)),
                                phi - accessor.getValue(ijk.offsetBy(0, 0, -1))};
        const float plus[3] = {accessor.getValue(ijk.offsetBy(1, 0, 0)) - phi,
                               accessor.getValue(ijk.offsetBy(0, 1, 0)) - phi,
                               accessor.getValue(ijk.offsetBy(0, 0, 1)) - phi};
        const float norm2 = godunovNorm2(phi > 0.0f, minus, plus);
        const float excess = std::sqrt(norm2) * inverseVoxel - 1.0f;
        const float smoothSign = phi / std::sqrt(phi * phi + norm2);
        out[value.pos()] = phi - voxel * smoothSign * excess;
      }
    }
  });
  // Only voxels at least a voxel from the surface take the step: their shifted values are at
  // least 0.2 voxel or at most -1.8 voxels, which it cannot carry across zero.
  const float outerPositive = voxel - shift;
  const float outerNegative = -voxel - shift;
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t i) {
    const float* in = &stepped[i * FloatLeaf::SIZE];
    for (auto value = leaves[i]->beginValueOn(); value; ++value) {
      if (*value >= outerPositive || *value <= outerNegative) {
        value.setValue(std::min(*value, in[value.pos()]));
      }
    }
  });
  shiftActive(leaves, shift - 1e-7f);
}

void trimBand(openvdb::FloatGrid& grid) {
  std::vector<FloatLeaf*> leaves;
  leaves.reserve(grid.tree().leafCount());
  grid.tree().getNodes(leaves);
  const float outside = grid.background();
  const float inside = -outside;
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t i) {
    for (auto value = leaves[i]->beginValueOn(); value; ++value) {
      const float v = *value;
      if (v < 0.0f ? !(v > inside) : !(v < outside)) {
        value.setValue(v < 0.0f ? inside : outside);
        value.setValueOff();
      }
    }
  });
  openvdb::tools::pruneLevelSet(grid.tree(), outside, inside);
}

}  // namespace d2vdb::detail
