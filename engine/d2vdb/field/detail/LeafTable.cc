// The leaf-origin hash that numbers a sparse level's active voxels (LeafTable.h).
#include "d2vdb/field/detail/LeafTable.h"

#include <limits>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {

std::size_t LeafTable::hash(const openvdb::Coord& c) const {
  const auto u = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)); };
  const std::uint64_t h = (u(c.x()) * 0x9E3779B97F4A7C15ull) ^ (u(c.y()) * 0xC2B2AE3D27D4EB4Full) ^
                          (u(c.z()) * 0x165667B19E3779F9ull);
  return static_cast<std::size_t>(h ^ (h >> 29)) & slotMask_;
}

LeafTable::LeafTable(std::vector<LeafEntry> entries) : entries_(std::move(entries)) {
  std::uint64_t total = 0;
  for (LeafEntry& entry : entries_) {
    if (entry.origin != blockOrigin(entry.origin)) {
      throw RuntimeFailure("internal error: a leaf origin is not a multiple of 8");
    }
    entry.base = static_cast<std::uint32_t>(total);
    std::uint32_t running = 0;
    for (int w = 0; w < 8; ++w) {
      entry.prefix[w] = static_cast<std::uint16_t>(running);
      running += static_cast<std::uint32_t>(countBits(entry.mask[w]));
    }
    total += running;
  }
  if (total > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError("the field has " + std::to_string(total) +
                     " active voxels, more than 2^32 records can address");
  }
  voxelCount_ = total;
  std::size_t capacity = 16;
  while (capacity < 2 * entries_.size()) capacity *= 2;
  slots_.assign(capacity, -1);
  slotMask_ = capacity - 1;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    std::size_t slot = hash(entries_[i].origin);
    while (slots_[slot] != -1) {
      if (entries_[static_cast<std::size_t>(slots_[slot])].origin == entries_[i].origin) {
        throw RuntimeFailure("internal error: two leaves of one level share an origin");
      }
      slot = (slot + 1) & slotMask_;
    }
    slots_[slot] = static_cast<std::int32_t>(i);
  }
}

std::int64_t LeafTable::findLeaf(const openvdb::Coord& ijk) const {
  if (slots_.empty()) return -1;
  const openvdb::Coord origin = blockOrigin(ijk);
  for (std::size_t slot = hash(origin);; slot = (slot + 1) & slotMask_) {
    const std::int32_t index = slots_[slot];
    if (index == -1) return -1;
    if (entries_[static_cast<std::size_t>(index)].origin == origin) return index;
  }
}

}  // namespace d2vdb::detail
