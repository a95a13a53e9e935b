// The voxels of a field's band (BandLayout.h).
#include "d2vdb/field/detail/BandLayout.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {
namespace {

/// Entries for the leaves of `tree` that have active voxels, in tree order.
std::vector<LeafEntry> activeLeafEntries(const openvdb::FloatTree& tree) {
  std::size_t count = 0;
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
    if (!leaf->getValueMask().isOff()) ++count;
  }
  std::vector<LeafEntry> entries(count);  // exact capacity: statistics() counts it
  std::size_t i = 0;
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
    if (leaf->getValueMask().isOff()) continue;
    entries[i].origin = leaf->origin();
    for (int w = 0; w < 8; ++w) {
      entries[i].mask[w] = leaf->getValueMask().getWord<std::uint64_t>(w);
    }
    ++i;
  }
  return entries;
}

/// `grid`, which must not be null.
openvdb::FloatGrid::ConstPtr nonNull(openvdb::FloatGrid::ConstPtr grid) {
  if (!grid) throw RuntimeFailure("internal error: a band layout without a grid");
  return grid;
}

}  // namespace

BandLayout::BandLayout(openvdb::FloatGrid::ConstPtr grid, const std::string& source)
    : grid_(nonNull(std::move(grid))), frame_(grid_->transform(), source) {
  if (grid_->tree().hasActiveTiles()) {
    throw InputError(source + ": the distance grid has active tiles (voxelize them first)");
  }
  table_ = LeafTable(activeLeafEntries(grid_->tree()));
  if (table_.voxelCount() == 0) throw InputError(source + ": the band has no active voxels");
}

double BandLayout::halfWidth() const {
  // The background is a float, so the quotient is known to a relative 6e-8 only: rounded to 6
  // significant digits (steps of at least 5e-7 relative), a band made with half-width 3 reports
  // 3, not 3.0000001192 (float(0.075) / 0.025) or 3.0000001444.
  const double quotient = std::abs(static_cast<double>(grid_->background())) / frame_.voxelSize();
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", quotient);
  return std::strtod(text, nullptr);
}

void BandLayout::replaceGrid(openvdb::FloatGrid::ConstPtr sameTopology) {
  if (!sameTopology || sameTopology->transform() != grid_->transform() ||
      !sameTopology->tree().hasSameTopology(grid_->tree())) {
    throw RuntimeFailure("internal error: a band's grid was replaced by one of another layout");
  }
  grid_ = std::move(sameTopology);
}

}  // namespace d2vdb::detail
