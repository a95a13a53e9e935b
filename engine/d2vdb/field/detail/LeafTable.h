// Numbering of the active voxels of a sparse level by leaf: a hash of 8^3 leaf origins, each
// with its active-voxel mask and the number of its first voxel, so that a voxel's record index
// costs one hash probe and a bit count. Used by the band and the coarse levels of the field.
#pragma once

#include <openvdb/openvdb.h>
#include <openvdb/util/NodeMasks.h>

#include <array>
#include <cstdint>
#include <vector>

namespace d2vdb::detail {

/// Number of set bits of `bits` (OpenVDB's own bit count, inline on every x86-64 baseline).
inline int countBits(std::uint64_t bits) {
  return static_cast<int>(openvdb::util::CountOn(openvdb::Index64{bits}));
}

/// The integer nearest to `value` (ties toward +infinity), inline: std::lround is a library call
/// on the x86-64 baseline. `value` must lie well inside the int range.
inline int nearestInt(double value) {
  const double shifted = value + 0.5;
  const int truncated = static_cast<int>(shifted);
  return truncated - (static_cast<double>(truncated) > shifted ? 1 : 0);
}

/// One 8^3 block of a sparse level: its origin (index space, multiples of 8), the active-voxel
/// mask (bit (x & 7) * 64 + (y & 7) * 8 + (z & 7), OpenVDB's leaf order) and the index of its
/// first record; records of the block's active voxels follow in mask order.
struct LeafEntry {
  openvdb::Coord origin;
  std::uint32_t base = 0;
  std::array<std::uint16_t, 8> prefix{};  ///< active voxels in mask words before word w
  std::array<std::uint64_t, 8> mask{};

  /// Whether the voxel at `offset` (0..511, mask order) is active.
  bool isOn(int offset) const { return ((mask[offset >> 6] >> (offset & 63)) & 1u) != 0; }
  /// Calls `visit(offset)` for every active voxel, in mask order (the order of its records).
  template <typename Visit>
  void forEachOn(Visit&& visit) const {
    for (int w = 0; w < 8; ++w) {
      for (std::uint64_t bits = mask[w]; bits != 0; bits &= bits - 1) {
        visit((w << 6) | __builtin_ctzll(bits));
      }
    }
  }
  /// Index-space coordinates of the voxel at `offset`.
  openvdb::Coord voxel(int offset) const {
    return origin + openvdb::Coord(offset >> 6, (offset >> 3) & 7, offset & 7);
  }
};

/// An immutable open-addressing hash of LeafEntry origins that numbers the active voxels: entry
/// by entry in the order given, voxels in mask order within an entry. Invariants (established by
/// the constructor): every entry's `base` and `prefix` agree with the masks and the order; origins
/// are distinct multiples of 8; the total fits in 32 bits.
class LeafTable {
 public:
  LeafTable() = default;
  /// Takes the entries (origins and masks; `base` and `prefix` are recomputed in the given order).
  /// Throws InputError when the active voxels exceed 2^32 - 1 and RuntimeFailure when two entries
  /// share an origin or an origin is not a multiple of 8 (a caller's bug).
  explicit LeafTable(std::vector<LeafEntry> entries);

  /// Index of the entry whose block contains voxel `ijk`, or -1.
  std::int64_t findLeaf(const openvdb::Coord& ijk) const;

  /// Record index of voxel `ijk` in entry `leaf` (which must contain it), or -1 when inactive.
  static std::int64_t recordIndex(const LeafEntry& leaf, const openvdb::Coord& ijk) {
    const int offset = ((ijk.x() & 7) << 6) | ((ijk.y() & 7) << 3) | (ijk.z() & 7);
    const int word = offset >> 6;
    const std::uint64_t bit = std::uint64_t{1} << (offset & 63);
    if ((leaf.mask[word] & bit) == 0) return -1;
    return static_cast<std::int64_t>(leaf.base) + leaf.prefix[word] +
           countBits(leaf.mask[word] & (bit - 1));
  }

  const std::vector<LeafEntry>& entries() const { return entries_; }
  /// Number of active voxels (records) the table numbers.
  std::uint64_t voxelCount() const { return voxelCount_; }
  /// Bytes held (capacities).
  std::uint64_t memoryBytes() const {
    return entries_.capacity() * sizeof(LeafEntry) + slots_.capacity() * sizeof(std::int32_t);
  }

  /// Origin of the block containing `ijk`.
  static openvdb::Coord blockOrigin(const openvdb::Coord& ijk) {
    return openvdb::Coord(ijk.x() & ~7, ijk.y() & ~7, ijk.z() & ~7);
  }

 private:
  std::size_t hash(const openvdb::Coord& origin) const;
  std::vector<LeafEntry> entries_;
  std::vector<std::int32_t> slots_;
  std::size_t slotMask_ = 0;
  std::uint64_t voxelCount_ = 0;
};

/// Voxel look-ups in one LeafTable that remember the last leaf found, for queries that move
/// little between calls. One per thread; the table must outlive it.
class LeafCursor {
 public:
  explicit LeafCursor(const LeafTable& table) : table_(&table) {}

  /// Record index of voxel `ijk`, or -1 when the table does not hold it.
  std::int64_t record(const openvdb::Coord& ijk) {
    const openvdb::Coord origin = LeafTable::blockOrigin(ijk);
    if (leaf_ < 0 || origin != origin_) {
      leaf_ = table_->findLeaf(ijk);
      origin_ = origin;
      if (leaf_ < 0) return -1;
    }
    return LeafTable::recordIndex(table_->entries()[static_cast<std::size_t>(leaf_)], ijk);
  }

 private:
  const LeafTable* table_;
  std::int64_t leaf_ = -1;
  openvdb::Coord origin_;
};

}  // namespace d2vdb::detail
