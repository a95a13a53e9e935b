// Parallel, deterministic marching cubes over the leaf blocks of a sparse grid (IsoSurface.h).
//
// Layout of the work: the "blocks" are the 8^3 cell blocks (cells named by their lowest corner)
// of every allocated leaf node and of the blocks just below one along any combination of axes, so
// every cell with a corner in a leaf is visited. They are numbered in (x, y, z) order of their
// origins, through a dense array over their bounding box when that is small next to the leaf
// count (any compact surface), else by sorting and hashing; each block keeps its 27 neighbours.
// Each crossed edge is owned by the block of the first visited cell around it (in a fixed order),
// which numbers it. Which block that is depends only on where the edge lies on the block boundary
// and on which neighbours exist, so it is tabulated once per distinct neighbour set.
//
// Classification works on bits. Every block's inside flags (value below the iso-value) are packed
// once into eight 64-bit words (uniform words for a block without a leaf, which holds one tile or
// background value). A block assembles the flags of its 9^3 cell corners from its own words and
// those of its seven upper neighbours as 81 rows of 9 bits (row (x, y), bit z): crossed edges are
// XORs of rows, cells with a crossing come from ANDs and ORs of four rows, and a block whose
// neighbours are all on one side is dropped before that.
//
// Pass 1 counts, per block, the triangles, the extra centre vertices and the crossed edges it
// owns (popcounts of the crossed-edge rows masked by the owned-edge table), reading values only
// for the face decider of ambiguous cells. It keeps the corner rows and the owned-edge rows with
// their prefix counts, so that a neighbour finds the number of a shared edge as a rank in
// constant time. A prefix sum gives every block its output ranges. Pass 2 gathers the values of
// each crossed block and one layer around it (for the central-difference normals) from the leaf
// buffers, then writes positions, normals and triangles straight into the output, mapping index
// space to world space without virtual calls for OpenVDB's linear maps.
#include "d2vdb/contour/IsoSurface.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <openvdb/math/Maps.h>

#include "d2vdb/contour/detail/CubeTables.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {
namespace {

using detail::CubeTables;
using openvdb::Coord;

constexpr int kBlockSize = 8;
constexpr int kCornerSpan = kBlockSize + 1;           // corner layers 0..8 of a block's cells
constexpr int kRowCount = kCornerSpan * kCornerSpan;  // corner rows (x, y) of a block
constexpr int kRowEdgeBits = 3 * kCornerSpan;         // edge bit 3 z + axis within a row
constexpr int kEdgeKeyCount = kRowCount * kRowEdgeBits;
constexpr int kSelfSlot = 13;  // neighborSlot(0, 0, 0)

/// Key of the edge from local corner (x, y, z) along `axis`; increasing in enumeration order.
constexpr int edgeKey(int x, int y, int z, int axis) {
  return (x * kCornerSpan + y) * kRowEdgeBits + 3 * z + axis;
}

/// Slot (0..26) of the neighbour block at offset (ox, oy, oz) in {-1, 0, 1}^3.
constexpr int neighborSlot(int ox, int oy, int oz) {
  return (ox + 1) * 9 + (oy + 1) * 3 + (oz + 1);
}

/// Block offset along one axis of the cell at local coordinate q (-1..8).
constexpr int blockStep(int q) {
  return q < 0 ? -1 : (q >= kBlockSize ? 1 : 0);
}

/// Boundary class of a local corner coordinate (0..8): 0 on the low face, 2 on the high face,
/// 1 between. Which block owns an edge depends only on the classes of its two other coordinates.
constexpr int boundaryClass(int q) {
  return q == 0 ? 0 : (q == kBlockSize ? 2 : 1);
}

/// Number of set bits (portable: the baseline x86-64 target has no popcount instruction).
constexpr int bitCount(std::uint32_t v) {
  v = v - ((v >> 1) & 0x55555555u);
  v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
  return static_cast<int>((((v + (v >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24);
}

/// The two axes other than `axis`, in increasing order.
inline std::array<int, 2> otherAxes(int axis) {
  return axis == 0 ? std::array<int, 2>{1, 2}
                   : (axis == 1 ? std::array<int, 2>{0, 2} : std::array<int, 2>{0, 1});
}

/// kSpread3[m] holds bit i of the 9-bit mask m at bit 3 i (edge rows interleave the three axes).
constexpr std::array<std::uint32_t, 512> kSpread3 = [] {
  std::array<std::uint32_t, 512> table{};
  for (unsigned mask = 0; mask < 512; ++mask) {
    for (int bit = 0; bit < 9; ++bit) table[mask] |= ((mask >> bit) & 1u) << (3 * bit);
  }
  return table;
}();

/// kSpread4[m] holds bit i of the 9-bit mask m at bit 4 i (cell cases interleave four rows).
constexpr std::array<std::uint64_t, 512> kSpread4 = [] {
  std::array<std::uint64_t, 512> table{};
  for (unsigned mask = 0; mask < 512; ++mask) {
    for (int bit = 0; bit < 9; ++bit) table[mask] |= std::uint64_t((mask >> bit) & 1u) << (4 * bit);
  }
  return table;
}();

/// Inside flags of the 8^3 values of a leaf-sized block: word x, bit 8 y + z.
using InsideWords = std::array<std::uint64_t, kBlockSize>;
constexpr InsideWords kAllOutside{};
constexpr InsideWords kAllInside{~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull};

/// Inside flags of a block's 9^3 cell corners: entry kCornerSpan * x + y, bit z.
using CornerRows = std::array<std::uint16_t, kRowCount>;

/// The crossed edges of corner row (x, y): bit 3 z + axis for the edge from (x, y, z) along
/// `axis` (edges leaving the block's corners, at x = 8 along x and so on, are not included).
inline std::uint32_t crossedEdgesOfRow(const CornerRows& rows, int x, int y) {
  const unsigned row = rows[x * kCornerSpan + y];
  const unsigned alongX = x < kBlockSize ? row ^ rows[(x + 1) * kCornerSpan + y] : 0u;
  const unsigned alongY = y < kBlockSize ? row ^ rows[x * kCornerSpan + y + 1] : 0u;
  const unsigned alongZ = (row ^ (row >> 1)) & 0xFFu;
  return kSpread3[alongX] | kSpread3[alongY] << 1 | kSpread3[alongZ] << 2;
}

/// Calls visit(x, y, z, caseIndex) for every cell of the block with corners on both sides, in
/// increasing (x, y, z) order.
template <typename Visit>
void forEachCrossedCell(const CornerRows& rows, Visit&& visit) {
  for (int x = 0; x < kBlockSize; ++x) {
    for (int y = 0; y < kBlockSize; ++y) {
      const unsigned r00 = rows[x * kCornerSpan + y], r10 = rows[(x + 1) * kCornerSpan + y];
      const unsigned r01 = rows[x * kCornerSpan + y + 1], r11 = rows[(x + 1) * kCornerSpan + y + 1];
      const unsigned any = r00 | r10 | r01 | r11, all = r00 & r10 & r01 & r11;
      unsigned mixed = (any | any >> 1) & ~(all & all >> 1) & 0xFFu;
      if (mixed == 0) continue;
      // Nibble z holds the four corners (x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1) at
      // height z: the case index of cell z is nibbles z and z + 1 (CubeTables' corner order).
      const std::uint64_t nibbles =
          kSpread4[r00] | kSpread4[r10] << 1 | kSpread4[r01] << 2 | kSpread4[r11] << 3;
      while (mixed != 0) {
        const int z = __builtin_ctz(mixed);
        mixed &= mixed - 1;
        visit(x, y, z, static_cast<int>((nibbles >> (4 * z)) & 0xFFu));
      }
    }
  }
}

/// Which block numbers each crossed edge of a block, given which of its 26 neighbours are blocks:
/// the block of the first visited cell around the edge, trying the cells whose lowest corner is
/// the edge's start minus (0, 0), (1, 0), (0, 1), (1, 1) along the edge's two other axes.
struct Ownership {
  /// Neighbour slot of the owner, at 9 axis + 3 classB + classC with classB and classC the
  /// boundary classes of the edge's coordinates along its two other axes (in increasing order).
  std::array<std::int8_t, 27> ownerSlot{};
  /// For a corner row of boundary classes (cx, cy), at 3 cx + cy: the edge bits the block owns,
  /// and those of them where some cell around the edge is not in a block (the surface would leave
  /// the visited cells there).
  std::array<std::uint32_t, 9> owned{}, gap{};
};

/// The neighbour slots of the four cells around an edge, in the order tried, at
/// 9 axis + 3 classB + classC (Ownership::ownerSlot).
constexpr std::array<std::array<int, 4>, 27> kCandidateSlots = [] {
  constexpr std::array<int, 3> kRepresentative{0, 1, kBlockSize};  // a coordinate of each class
  constexpr std::array<std::array<int, 2>, 4> kCandidates{{{0, 0}, {1, 0}, {0, 1}, {1, 1}}};
  std::array<std::array<int, 4>, 27> slots{};
  for (int axis = 0; axis < 3; ++axis) {
    const int b = axis == 0 ? 1 : 0, c = axis == 2 ? 1 : 2;  // the other axes, increasing
    for (int classB = 0; classB < 3; ++classB) {
      for (int classC = 0; classC < 3; ++classC) {
        for (int i = 0; i < 4; ++i) {
          std::array<int, 3> step{0, 0, 0};
          step[b] = blockStep(kRepresentative[classB] - kCandidates[i][0]);
          step[c] = blockStep(kRepresentative[classC] - kCandidates[i][1]);
          slots[9 * axis + 3 * classB + classC][i] = neighborSlot(step[0], step[1], step[2]);
        }
      }
    }
  }
  return slots;
}();

/// The ownership rule above for a block with neighbour mask `memberMask`.
Ownership ownershipOf(std::uint32_t memberMask) {
  static constexpr std::array<std::uint32_t, 3> kClassBits = [] {
    std::array<std::uint32_t, 3> bits{};  // bits 3 z (axis 0) of the z in each class
    for (int z = 0; z <= kBlockSize; ++z) bits[boundaryClass(z)] |= 1u << (3 * z);
    return bits;
  }();
  Ownership result;
  std::array<bool, 27> missing{};
  for (int index = 0; index < 27; ++index) {
    int owner = -1;
    for (const int slot : kCandidateSlots[index]) {
      if ((memberMask >> slot) & 1u) {
        if (owner < 0) owner = slot;
      } else {
        missing[index] = true;
      }
    }
    result.ownerSlot[index] = static_cast<std::int8_t>(owner);
  }
  for (int cx = 0; cx < 3; ++cx) {
    for (int cy = 0; cy < 3; ++cy) {
      for (int cz = 0; cz < 3; ++cz) {
        // Other axes: (y, z) for x-edges, (x, z) for y-edges, (x, y) for z-edges.
        const std::array<int, 3> index{3 * cy + cz, 9 + 3 * cx + cz, 18 + 3 * cx + cy};
        for (int axis = 0; axis < 3; ++axis) {
          if (result.ownerSlot[index[axis]] != kSelfSlot) continue;
          result.owned[3 * cx + cy] |= kClassBits[cz] << axis;
          if (missing[index[axis]]) result.gap[3 * cx + cy] |= kClassBits[cz] << axis;
        }
      }
    }
  }
  return result;
}

/// What pass 1 keeps of a block with crossed edges: its corner rows for pass 2, and the edges
/// it numbers for its neighbours' look-ups.
struct CrossedBlock {
  CornerRows rows;
  std::array<std::uint32_t, kRowCount> owned;   ///< owned crossed edges of each corner row
  std::array<std::uint16_t, kRowCount> before;  ///< owned crossed edges in the rows before
};

/// Per-block results of pass 1.
struct BlockCounts {
  std::unique_ptr<CrossedBlock> crossed;  ///< null when no edge of the block's cells is crossed
  std::uint32_t ownership = 0;            ///< index of the block's ownership rule
  std::uint32_t ownedVertices = 0;
  std::uint32_t centerVertices = 0;
  std::uint32_t triangles = 0;
  std::uint32_t gapEdges = 0;
};

/// Reads of the values around one block: local coordinates -1..9 fall into the 27 neighbour
/// slots, each either a leaf buffer or one tile or background value.
template <typename ValueT>
class NeighborValues {
 public:
  NeighborValues() = default;
  NeighborValues(const NeighborValues&) = delete;
  NeighborValues& operator=(const NeighborValues&) = delete;

  /// Reads slot `slot` from a leaf buffer.
  void setLeaf(int slot, const ValueT* data) {
    data_[slot] = data;
    mask_[slot] = 511;
  }
  /// Makes every value of slot `slot` equal to `value`.
  void setFill(int slot, ValueT value) {
    fill_[slot] = value;
    data_[slot] = &fill_[slot];
    mask_[slot] = 0;
  }
  /// The value at local coordinates (x, y, z), each in -1..9.
  ValueT operator()(int x, int y, int z) const {
    const int slot = slotOf(x) * 9 + slotOf(y) * 3 + slotOf(z);
    const int offset = ((x & 7) << 6) | ((y & 7) << 3) | (z & 7);
    return data_[slot][offset & mask_[slot]];
  }
  /// Copies the values at (x, y, z) for z = 0..8, and with `outer` also z = -1 and 9, to
  /// out[z + 1].
  void copyRow(int x, int y, bool outer, ValueT* out) const {
    const int rowSlot = slotOf(x) * 9 + slotOf(y) * 3;
    const int rowOffset = ((x & 7) << 6) | ((y & 7) << 3);
    const int middle = rowSlot + 1, above = rowSlot + 2;
    if (mask_[middle] != 0) {
      std::copy_n(data_[middle] + rowOffset, kBlockSize, out + 1);
    } else {
      std::fill_n(out + 1, kBlockSize, *data_[middle]);
    }
    out[kBlockSize + 1] = data_[above][rowOffset & mask_[above]];
    if (outer) {
      out[0] = data_[rowSlot][(rowOffset | 7) & mask_[rowSlot]];
      out[kBlockSize + 2] = data_[above][(rowOffset | 1) & mask_[above]];
    }
  }

 private:
  /// Slot index (0, 1, 2) along one axis of local coordinate q (-1..9).
  static int slotOf(int q) { return (q + kBlockSize) >> 3; }

  std::array<const ValueT*, 27> data_{};
  std::array<int, 27> mask_{};
  std::array<ValueT, 27> fill_{};
};

/// A block's corner values and one layer around them (local coordinates -1..9), z contiguous,
/// gathered once so that the vertices read them by plain index arithmetic.
template <typename ValueT>
class Region {
 public:
  static constexpr int kSpan = kCornerSpan + 2;
  static constexpr std::array<int, 3> kStride{kSpan * kSpan, kSpan, 1};

  /// Index of local coordinates (x, y, z), each in -1..9.
  static constexpr int index(int x, int y, int z) {
    return ((x + 1) * kSpan + (y + 1)) * kSpan + (z + 1);
  }
  /// Copies the values at local coordinates 0..8, and with `outer` -1..9, along every axis from
  /// `source`.
  void gather(const NeighborValues<ValueT>& source, bool outer) {
    const int low = outer ? -1 : 0, high = outer ? kCornerSpan : kBlockSize;
    for (int x = low; x <= high; ++x) {
      for (int y = low; y <= high; ++y) source.copyRow(x, y, outer, &values_[index(x, y, -1)]);
    }
  }
  /// The value at index i (see index()).
  ValueT operator[](int i) const { return values_[i]; }
  /// The value at local coordinates (x, y, z).
  ValueT operator()(int x, int y, int z) const { return values_[index(x, y, z)]; }
  /// Index-space gradient by central differences at the corner of index i.
  openvdb::Vec3d gradient(int i) const {
    return 0.5 *
           openvdb::Vec3d(static_cast<double>(values_[i + kStride[0]]) - values_[i - kStride[0]],
                          static_cast<double>(values_[i + kStride[1]]) - values_[i - kStride[1]],
                          static_cast<double>(values_[i + 1]) - values_[i - 1]);
  }

 private:
  std::array<ValueT, kSpan * kSpan * kSpan> values_;
};

/// The face decisions (bit f: inside corners of ambiguous face f joined) of the cell at local
/// (x, y, z) by the asymptotic decider (CubeTables.h).
template <typename Values>
std::uint8_t decideFaces(const Values& values, int x, int y, int z, int caseIndex,
                         std::uint8_t ambiguous, double iso) {
  static const std::array<std::array<int, 4>, 6> kFaceCorners = [] {
    std::array<std::array<int, 4>, 6> corners{};
    for (int face = 0; face < 6; ++face) corners[face] = detail::faceCorners(face);
    return corners;
  }();
  std::array<double, 8> relative{};
  for (int corner = 0; corner < 8; ++corner) {
    const auto offset = detail::cornerOffset(corner);
    relative[corner] =
        static_cast<double>(values(x + offset[0], y + offset[1], z + offset[2])) - iso;
  }
  std::uint8_t joined = 0;
  for (int face = 0; face < 6; ++face) {
    if (((ambiguous >> face) & 1) == 0) continue;
    const auto& c = kFaceCorners[face];
    const double diagonal02 = relative[c[0]] * relative[c[2]];
    const double diagonal13 = relative[c[1]] * relative[c[3]];
    const bool corner0Inside = ((caseIndex >> c[0]) & 1) != 0;
    if (corner0Inside ? diagonal02 > diagonal13 : diagonal13 > diagonal02) joined |= 1u << face;
  }
  return joined;
}

/// Key offset, from the key of a cell's lowest corner, of each of the cell's 12 edges.
const std::array<int, detail::kCubeEdges>& cellEdgeKeyOffsets() {
  static const std::array<int, detail::kCubeEdges> offsets = [] {
    std::array<int, detail::kCubeEdges> result{};
    for (int edge = 0; edge < detail::kCubeEdges; ++edge) {
      const auto start = detail::cornerOffset(detail::edgeStartCorner(edge));
      result[edge] = edgeKey(start[0], start[1], start[2], detail::edgeAxis(edge));
    }
    return result;
  }();
  return offsets;
}

/// Calls visit(map) with the grid's map as its concrete type when it is one of OpenVDB's linear
/// maps (whose methods are final, so the calls are direct), else as MapBase (virtual calls).
template <typename Visit>
void withConcreteMap(const openvdb::math::MapBase& map, Visit&& visit) {
  namespace math = openvdb::math;
  if (map.isType<math::UniformScaleMap>() || map.isType<math::ScaleMap>()) {
    visit(static_cast<const math::ScaleMap&>(map));
  } else if (map.isType<math::UniformScaleTranslateMap>() ||
             map.isType<math::ScaleTranslateMap>()) {
    visit(static_cast<const math::ScaleTranslateMap&>(map));
  } else if (map.isType<math::TranslationMap>()) {
    visit(static_cast<const math::TranslationMap&>(map));
  } else if (map.isType<math::AffineMap>()) {
    visit(static_cast<const math::AffineMap&>(map));
  } else {
    visit(map);
  }
}

/// The sorted blocks to visit and, for each, its 27 neighbours (index or -1) and its leaf.
template <typename LeafT>
struct BlockSet {
  std::vector<Coord> origins;
  std::vector<std::array<std::int32_t, 27>> neighbors;
  std::vector<std::uint32_t> memberMask;  ///< bit slot set when that neighbour is a block
  std::vector<const LeafT*> leaves;       ///< the block's leaf node, or null
};

/// Lexicographic (x, y, z) order of block origins.
bool coordLess(const Coord& a, const Coord& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

/// Open-addressing map from block origin to block index (read-only after construction).
class BlockHashIndex {
 public:
  explicit BlockHashIndex(const std::vector<Coord>& origins) : origins_(origins) {
    std::size_t capacity = 16;
    while (capacity < 2 * origins.size()) capacity *= 2;
    slots_.assign(capacity, -1);
    mask_ = capacity - 1;
    for (std::size_t i = 0; i < origins.size(); ++i) {
      std::size_t slot = hash(origins[i]);
      while (slots_[slot] != -1) slot = (slot + 1) & mask_;
      slots_[slot] = static_cast<std::int32_t>(i);
    }
  }
  /// The index of the block at `origin`, or -1.
  std::int32_t find(const Coord& origin) const {
    for (std::size_t slot = hash(origin);; slot = (slot + 1) & mask_) {
      const std::int32_t index = slots_[slot];
      if (index == -1 || origins_[index] == origin) return index;
    }
  }

 private:
  /// Home slot of a block origin.
  std::size_t hash(const Coord& c) const {
    const auto u = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)); };
    const std::uint64_t h = (u(c.x()) * 0x9E3779B97F4A7C15ull) ^
                            (u(c.y()) * 0xC2B2AE3D27D4EB4Full) ^ (u(c.z()) * 0x165667B19E3779F9ull);
    return static_cast<std::size_t>(h ^ (h >> 29)) & mask_;
  }
  const std::vector<Coord>& origins_;
  std::vector<std::int32_t> slots_;
  std::size_t mask_ = 0;
};

/// Dense array of block indices over a box of block positions (block origin / 8), with the
/// blocks numbered in (x, y, z) order, as sorting would.
class BlockGridIndex {
 public:
  /// Covers block positions low..high (inclusive); false from fits() when that box holds more
  /// than `maxCells` cells.
  BlockGridIndex(const Coord& low, const Coord& high, double maxCells) : low_(low) {
    for (int axis = 0; axis < 3; ++axis) size_[axis] = std::int64_t(high[axis]) - low[axis] + 1;
    fits_ = double(size_[0]) * double(size_[1]) * double(size_[2]) <= maxCells;
    if (fits_) cells_.assign(static_cast<std::size_t>(size_[0] * size_[1] * size_[2]), -1);
  }
  /// True when the box is small enough to be indexed densely.
  bool fits() const { return fits_; }
  /// Marks the block at `origin` as present.
  void mark(const Coord& origin) { cells_[cell(origin)] = 0; }
  /// Numbers the marked blocks in (x, y, z) order and appends their origins to `origins`.
  void number(std::vector<Coord>& origins) {
    std::int32_t next = 0;
    std::size_t i = 0;
    for (std::int64_t x = 0; x < size_[0]; ++x) {
      for (std::int64_t y = 0; y < size_[1]; ++y) {
        for (std::int64_t z = 0; z < size_[2]; ++z, ++i) {
          if (cells_[i] < 0) continue;
          cells_[i] = next++;
          origins.emplace_back(static_cast<int>((low_.x() + x) * kBlockSize),
                               static_cast<int>((low_.y() + y) * kBlockSize),
                               static_cast<int>((low_.z() + z) * kBlockSize));
        }
      }
    }
  }
  /// The index of the block at `origin` (inside the box), or -1.
  std::int32_t find(const Coord& origin) const { return cells_[cell(origin)]; }

 private:
  /// Position in cells_ of the block at `origin`.
  std::size_t cell(const Coord& origin) const {
    return static_cast<std::size_t>(
        ((origin.x() / kBlockSize - low_.x()) * size_[1] + (origin.y() / kBlockSize - low_.y())) *
            size_[2] +
        (origin.z() / kBlockSize - low_.z()));
  }
  Coord low_;
  std::array<std::int64_t, 3> size_{};
  bool fits_ = false;
  std::vector<std::int32_t> cells_;
};

/// Fills the neighbour tables of `set` with `find` (block origin to index or -1).
template <typename LeafT, typename Find>
void findNeighbors(BlockSet<LeafT>& set, const Find& find) {
  set.neighbors.resize(set.origins.size());
  set.memberMask.resize(set.origins.size());
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, set.origins.size(), 256),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
          std::uint32_t mask = 0;
          for (int ox = -1; ox <= 1; ++ox) {
            for (int oy = -1; oy <= 1; ++oy) {
              for (int oz = -1; oz <= 1; ++oz) {
                const int slot = neighborSlot(ox, oy, oz);
                const std::int32_t found =
                    find(set.origins[b] + Coord(ox * kBlockSize, oy * kBlockSize, oz * kBlockSize));
                set.neighbors[b][slot] = found;
                if (found >= 0) mask |= 1u << slot;
              }
            }
          }
          set.memberMask[b] = mask;
        }
      });
}

/// The blocks of `tree`'s leaf nodes and of the blocks just below them along any axes. A dense
/// index over their bounding box when it has at most 64 cells per leaf (compact level sets),
/// else sorting and hashing.
template <typename TreeT>
BlockSet<typename TreeT::LeafNodeType> collectBlocks(const TreeT& tree) {
  using LeafT = typename TreeT::LeafNodeType;
  BlockSet<LeafT> set;
  std::vector<const LeafT*> leaves;
  leaves.reserve(tree.leafCount());
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) leaves.push_back(&*leaf);
  if (leaves.empty()) return set;
  const auto forEachBlock = [](const Coord& leafOrigin, auto&& visit) {
    for (int corner = 0; corner < 8; ++corner) {
      visit(leafOrigin - Coord((corner & 1) * kBlockSize, ((corner >> 1) & 1) * kBlockSize,
                               ((corner >> 2) & 1) * kBlockSize));
    }
  };
  Coord low = leaves.front()->origin(), high = low;
  for (const LeafT* leaf : leaves) {
    low.minComponent(leaf->origin());
    high.maxComponent(leaf->origin());
  }
  // Block positions of the blocks (leaves and up to one block below) and their neighbours.
  const auto position = [](const Coord& origin, int shift) {
    return Coord(origin.x() / kBlockSize + shift, origin.y() / kBlockSize + shift,
                 origin.z() / kBlockSize + shift);
  };
  BlockGridIndex grid(position(low, -2), position(high, 1), 64.0 * double(leaves.size()) + 4096.0);
  if (grid.fits()) {
    for (const LeafT* leaf : leaves) {
      forEachBlock(leaf->origin(), [&](const Coord& origin) { grid.mark(origin); });
    }
    set.origins.reserve(leaves.size() * 4);
    grid.number(set.origins);
    findNeighbors(set, [&grid](const Coord& origin) { return grid.find(origin); });
    set.leaves.assign(set.origins.size(), nullptr);
    for (const LeafT* leaf : leaves) set.leaves[grid.find(leaf->origin())] = leaf;
    return set;
  }
  set.origins.reserve(leaves.size() * 8);
  for (const LeafT* leaf : leaves) {
    forEachBlock(leaf->origin(), [&](const Coord& origin) { set.origins.push_back(origin); });
  }
  tbb::parallel_sort(set.origins.begin(), set.origins.end(), coordLess);
  set.origins.erase(std::unique(set.origins.begin(), set.origins.end()), set.origins.end());
  const BlockHashIndex index(set.origins);
  findNeighbors(set, [&index](const Coord& origin) { return index.find(origin); });
  set.leaves.assign(set.origins.size(), nullptr);
  for (const LeafT* leaf : leaves) set.leaves[index.find(leaf->origin())] = leaf;
  return set;
}

/// Runs body over [0, count) in parallel, in slices when progress is reported.
template <typename Body>
void forBlocks(std::size_t count, const char* stage, const ProgressCallback& progress,
               const Body& body) {
  const std::size_t slices = progress && count > 0 ? 20 : 1;
  for (std::size_t slice = 0; slice < slices; ++slice) {
    const std::size_t begin = count * slice / slices, end = count * (slice + 1) / slices;
    if (begin < end) tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 8), body);
    if (progress) {
      progress(stage, count > 0 ? static_cast<double>(end) / static_cast<double>(count) : 1.0);
    }
  }
}

/// Messages show numbers with six significant digits.
constexpr int kDigits = 6;

/// One extraction: collects the blocks, runs the two passes and owns the mesh being written.
template <typename GridT>
class Extractor {
  using ValueT = typename GridT::ValueType;
  using AccessorT = typename GridT::ConstAccessor;

 public:
  Extractor(const GridT& grid, const IsoSurfaceOptions& options, const ProgressCallback& progress)
      : grid_(grid), options_(options), progress_(progress), tables_(CubeTables::instance()) {
    for (int caseIndex = 0; caseIndex < 256; ++caseIndex) {
      plainCells_[caseIndex] = &tables_.triangulation(caseIndex, 0);
    }
  }

  /// Extracts the mesh (IsoSurface.h); call once.
  TriangleMesh run() {
    checkIsoValue();
    blocks_ = collectBlocks(grid_.tree());
    const std::size_t blockCount = blocks_.origins.size();
    prepareBlocks();
    prepareOwnerships();
    counts_.resize(blockCount);
    forBlocks(blockCount, "contour: counting", progress_,
              [this](const tbb::blocked_range<std::size_t>& range) { countBlocks(range); });

    vertexBase_.resize(blockCount + 1);
    triangleBase_.resize(blockCount + 1);
    std::uint64_t vertices = 0, triangles = 0, gaps = 0;
    for (std::size_t b = 0; b < blockCount; ++b) {
      vertexBase_[b] = vertices;
      triangleBase_[b] = triangles;
      vertices += counts_[b].ownedVertices + counts_[b].centerVertices;
      triangles += counts_[b].triangles;
      gaps += counts_[b].gapEdges;
    }
    vertexBase_[blockCount] = vertices;
    triangleBase_[blockCount] = triangles;
    if (gaps > 0) throwOutsideBand(gaps);
    // Pass 2 reads the corner rows kept by pass 1: release the inside flags before the output.
    std::vector<InsideWords>().swap(inside_);
    std::vector<std::uint8_t>().swap(side_);
    if (vertices > std::numeric_limits<TriangleMesh::Index>::max()) {
      throw RuntimeFailure("the iso-surface has " + std::to_string(vertices) +
                           " vertices, more than a mesh with 32-bit indices can hold");
    }

    mesh_.positions.resize(vertices);
    if (options_.computeNormals) mesh_.normals.resize(vertices);
    mesh_.triangles.resize(triangles);
    withConcreteMap(*grid_.transform().baseMap(), [&](const auto& map) {
      forBlocks(blockCount, "contour: meshing", progress_,
                [&](const tbb::blocked_range<std::size_t>& range) { meshBlocks(range, map); });
    });
    return std::move(mesh_);
  }

 private:
  /// Side of a block's values: all outside, all inside, or both.
  enum Side : std::uint8_t { kOutside = 0, kInside = 1, kMixed = 2 };

  /// True for a level set (GRID_LEVEL_SET), whose band limits the iso-value.
  bool isLevelSet() const { return grid_.getGridClass() == openvdb::GRID_LEVEL_SET; }

  /// The largest |iso| a level set's band represents: background minus one voxel.
  double levelSetLimit() const {
    return std::abs(static_cast<double>(grid_.background())) - grid_.voxelSize()[0];
  }

  /// Throws InputError for a non-finite iso-value or one beyond a level set's band.
  void checkIsoValue() const {
    if (!std::isfinite(options_.isoValue)) {
      throw InputError("the iso-value must be a finite number");
    }
    // Beyond this, some edge vertices would be interpolated from the background value instead
    // of a stored distance (the edge's far end lies outside the band).
    if (isLevelSet() && std::abs(options_.isoValue) > levelSetLimit()) throwOutsideBand(0);
  }

  /// Throws the InputError for an iso-value the band cannot represent (`gapEdges` edges where
  /// the surface leaves the visited cells, 0 when found from the level set's background).
  [[noreturn]] void throwOutsideBand(std::uint64_t gapEdges) const {
    std::string message = "iso-value " + formatNumber(options_.isoValue, kDigits) +
                          " lies outside what the grid's narrow band can represent";
    if (gapEdges > 0) {
      message += ": the iso-surface leaves the stored band at " + std::to_string(gapEdges) +
                 " cell edges, so the mesh would have holes";
    }
    if (isLevelSet()) {
      const double limit = levelSetLimit();
      message += (gapEdges > 0 ? "; this" : ": this") + std::string(" level set (background ") +
                 formatNumber(static_cast<double>(grid_.background()), kDigits) + ", voxel size " +
                 formatNumber(grid_.voxelSize()[0], kDigits) +
                 ") holds iso-surfaces for |iso| up to about " +
                 formatNumber(std::max(0.0, limit), kDigits) +
                 " (background minus one voxel, so that both ends of every crossed edge hold "
                 "stored distances)";
      if (std::abs(options_.isoValue) > limit) {
        message += ", which this iso-value exceeds by " +
                   formatNumber(std::abs(options_.isoValue) - std::max(0.0, limit), kDigits);
      }
      message += "; rebuild the level set with a wider band (--half-width)";
    }
    throw InputError(message + ".");
  }

  /// True when `value` is inside (below the iso-value).
  bool isInside(ValueT value) const { return static_cast<double>(value) < options_.isoValue; }

  /// The smallest ValueT t with value < t exactly when isInside(value), so that leaf buffers are
  /// classified without conversions.
  ValueT insideThreshold() const {
    using Limits = std::numeric_limits<ValueT>;
    const double iso = options_.isoValue;
    if (iso > static_cast<double>(Limits::max())) return Limits::infinity();
    if (iso < static_cast<double>(Limits::lowest())) return Limits::lowest();
    ValueT threshold = static_cast<ValueT>(iso);
    if (static_cast<double>(threshold) < iso) {
      threshold = std::nextafter(threshold, Limits::infinity());
    }
    return threshold;
  }

  /// Finds every block's leaf buffer (or its tile or background value) and packs its inside
  /// flags.
  void prepareBlocks() {
    const std::size_t blockCount = blocks_.origins.size();
    leafData_.assign(blockCount, nullptr);
    fillValue_.assign(blockCount, ValueT(0));
    inside_.resize(blockCount);
    side_.resize(blockCount);
    const ValueT threshold = insideThreshold();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blockCount, 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        auto accessor = grid_.getConstAccessor();
                        for (std::size_t b = range.begin(); b != range.end(); ++b) {
                          const Coord& origin = blocks_.origins[b];
                          if (const auto* leaf = blocks_.leaves[b]) {
                            leafData_[b] = leaf->buffer().data();
                            inside_[b] = insideWords(leafData_[b], threshold);
                            side_[b] = sideOf(inside_[b]);
                          } else {
                            fillValue_[b] = accessor.getValue(origin);
                            side_[b] = isInside(fillValue_[b]) ? kInside : kOutside;
                            inside_[b] = side_[b] == kInside ? kAllInside : kAllOutside;
                          }
                        }
                      });
  }

  /// The inside flags of a leaf buffer (value below `threshold`).
  static InsideWords insideWords(const ValueT* data, ValueT threshold) {
    InsideWords words{};
    for (int x = 0; x < kBlockSize; ++x) {
      std::array<std::uint8_t, 64> flags;  // one byte per value: a loop compilers vectorize
      for (int i = 0; i < 64; ++i) flags[i] = data[64 * x + i] < threshold ? 1 : 0;
      std::uint64_t word = 0;
      for (int y = 0; y < kBlockSize; ++y) {
        std::uint64_t bytes = 0;  // flag z in byte z
        for (int z = 0; z < kBlockSize; ++z) bytes |= std::uint64_t(flags[8 * y + z]) << (8 * z);
        // The multiplication moves byte z's low bit to bit 56 + z without carries.
        word |= ((bytes * 0x0102040810204080ull) >> 56) << (8 * y);
      }
      words[x] = word;
    }
    return words;
  }

  /// Whether inside flags are all clear, all set, or mixed.
  static Side sideOf(const InsideWords& words) {
    std::uint64_t any = 0, all = ~0ull;
    for (const std::uint64_t word : words) {
      any |= word;
      all &= word;
    }
    return any == 0 ? kOutside : (all == ~0ull ? kInside : kMixed);
  }

  /// Tabulates the ownership rule for every distinct neighbour mask of the blocks.
  void prepareOwnerships() {
    ownershipMasks_ = blocks_.memberMask;
    tbb::parallel_sort(ownershipMasks_.begin(), ownershipMasks_.end());
    ownershipMasks_.erase(std::unique(ownershipMasks_.begin(), ownershipMasks_.end()),
                          ownershipMasks_.end());
    ownerships_.resize(ownershipMasks_.size());
    for (std::size_t i = 0; i < ownershipMasks_.size(); ++i) {
      ownerships_[i] = ownershipOf(ownershipMasks_[i]);
    }
  }

  /// Index in ownerships_ of block `block`'s ownership rule.
  std::uint32_t ownershipIndex(std::size_t block) const {
    const auto found =
        std::lower_bound(ownershipMasks_.begin(), ownershipMasks_.end(), blocks_.memberMask[block]);
    return static_cast<std::uint32_t>(found - ownershipMasks_.begin());
  }

  /// Index-space origin of the neighbour in `slot` of block `block`.
  Coord slotOrigin(std::size_t block, int slot) const {
    return blocks_.origins[block] + Coord((slot / 9 - 1) * kBlockSize,
                                          ((slot / 3) % 3 - 1) * kBlockSize,
                                          (slot % 3 - 1) * kBlockSize);
  }

  /// Assembles the corner rows of block `block`; false when all corners are on one side.
  bool buildRows(std::size_t block, AccessorT& accessor, CornerRows& rows) const {
    // The upper neighbours (offsets 0 and +1), index ox | oy << 1 | oz << 2.
    std::array<const InsideWords*, 8> words{};
    unsigned sides = 0;  // bit kOutside / kInside / kMixed of each neighbour's side
    for (int i = 0; i < 8; ++i) {
      const int slot = neighborSlot(i & 1, (i >> 1) & 1, i >> 2);
      const std::int32_t neighbor = blocks_.neighbors[block][slot];
      if (neighbor >= 0) {
        words[i] = &inside_[neighbor];
        sides |= 1u << side_[neighbor];
      } else {
        const bool inside = isInside(accessor.getValue(slotOrigin(block, slot)));
        words[i] = inside ? &kAllInside : &kAllOutside;
        sides |= 1u << (inside ? kInside : kOutside);
      }
    }
    if (sides == 1u << kOutside || sides == 1u << kInside) return false;
    unsigned any = 0, all = 0x1FFu;
    for (int x = 0; x <= kBlockSize; ++x) {
      const int across = x >> 3, lx = x & 7;
      const std::uint64_t low = (*words[across])[lx], high = (*words[across | 4])[lx];
      std::uint16_t* row = &rows[x * kCornerSpan];
      for (int y = 0; y < kBlockSize; ++y) {
        row[y] =
            static_cast<std::uint16_t>(((low >> (8 * y)) & 0xFFu) | ((high >> (8 * y)) & 1u) << 8);
      }
      row[kBlockSize] = static_cast<std::uint16_t>(((*words[across | 2])[lx] & 0xFFu) |
                                                   ((*words[across | 6])[lx] & 1u) << 8);
      for (int y = 0; y <= kBlockSize; ++y) {
        any |= row[y];
        all &= row[y];
      }
    }
    return any != 0 && all != 0x1FFu;
  }

  /// Points `values` at the neighbours of block `block`: all 27, or with `upperOnly` the 8 at
  /// offsets 0 and +1 (enough for local coordinates 0..8).
  void loadValues(std::size_t block, AccessorT& accessor, bool upperOnly,
                  NeighborValues<ValueT>& values) const {
    for (int ox = upperOnly ? 0 : -1; ox <= 1; ++ox) {
      for (int oy = upperOnly ? 0 : -1; oy <= 1; ++oy) {
        for (int oz = upperOnly ? 0 : -1; oz <= 1; ++oz) {
          const int slot = neighborSlot(ox, oy, oz);
          const std::int32_t neighbor = blocks_.neighbors[block][slot];
          if (neighbor >= 0 && leafData_[neighbor]) {
            values.setLeaf(slot, leafData_[neighbor]);
          } else {
            values.setFill(slot, neighbor >= 0 ? fillValue_[neighbor]
                                               : accessor.getValue(slotOrigin(block, slot)));
          }
        }
      }
    }
  }

  /// The triangulation of the cell at local (x, y, z) with case `caseIndex`; `values` (anything
  /// with operator()(x, y, z)) is asked for corner values only when the case has ambiguous faces.
  template <typename ValuesFn>
  const detail::CellTriangulation& cellTriangulation(int x, int y, int z, int caseIndex,
                                                     const ValuesFn& values) const {
    const std::uint8_t ambiguous = tables_.ambiguousFaces(caseIndex);
    if (ambiguous == 0) return *plainCells_[caseIndex];
    return tables_.triangulation(
        caseIndex, decideFaces(values(), x, y, z, caseIndex, ambiguous, options_.isoValue));
  }

  /// Pass 1: counts vertices, triangles and gap edges of each block and keeps its owned edges.
  void countBlocks(const tbb::blocked_range<std::size_t>& range) {
    auto accessor = grid_.getConstAccessor();
    CornerRows rows;
    NeighborValues<ValueT> values;
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      if (!buildRows(b, accessor, rows)) continue;
      BlockCounts& counts = counts_[b];
      counts.ownership = ownershipIndex(b);
      const Ownership& ownership = ownerships_[counts.ownership];
      counts.crossed.reset(new CrossedBlock);  // not value-initialized: all written below
      CrossedBlock& block = *counts.crossed;
      block.rows = rows;
      std::uint32_t owned = 0, gaps = 0;
      for (int x = 0; x <= kBlockSize; ++x) {
        for (int y = 0; y <= kBlockSize; ++y) {
          const int row = x * kCornerSpan + y;
          const std::uint32_t crossed = crossedEdgesOfRow(rows, x, y);
          const int rowClass = 3 * boundaryClass(x) + boundaryClass(y);
          const std::uint32_t mask = crossed & ownership.owned[rowClass];
          block.owned[row] = mask;
          block.before[row] = static_cast<std::uint16_t>(owned);
          if (mask != 0) owned += static_cast<std::uint32_t>(bitCount(mask));
          if ((crossed & ownership.gap[rowClass]) != 0) {
            gaps += static_cast<std::uint32_t>(bitCount(crossed & ownership.gap[rowClass]));
          }
        }
      }
      counts.ownedVertices = owned;
      counts.gapEdges = gaps;
      bool loaded = false;
      const auto upperValues = [&]() -> const NeighborValues<ValueT>& {
        if (!loaded) loadValues(b, accessor, true, values);
        loaded = true;
        return values;
      };
      forEachCrossedCell(rows, [&](int x, int y, int z, int caseIndex) {
        const auto& cell = cellTriangulation(x, y, z, caseIndex, upperValues);
        counts.triangles += cell.triangleCount;
        if (cell.centerEdges) ++counts.centerVertices;
      });
    }
  }

  /// Parameter of the vertex along an edge from value v0 to v1 (they straddle the iso-value).
  double edgeParameter(double v0, double v1) const {
    const double t = (options_.isoValue - v0) / (v1 - v0);
    if (options_.raw) return std::clamp(t, 0.0, 1.0);
    return std::clamp(t, kCornerClearance, 1.0 - kCornerClearance);
  }

  /// Unit world-space normal from an index-space gradient (the fallback axis and sign when the
  /// gradient vanishes).
  template <typename MapT>
  static Eigen::Vector3f worldNormal(const MapT& map, const openvdb::Vec3d& indexGradient,
                                     const openvdb::Vec3d& indexPosition, int fallbackAxis,
                                     double fallbackSign) {
    openvdb::Vec3d gradient = map.applyIJT(indexGradient, indexPosition);
    const double length = gradient.length();
    if (!(length > 1e-30) || !std::isfinite(length)) {
      gradient = openvdb::Vec3d(0.0);
      gradient[fallbackAxis] = fallbackSign;
    } else {
      gradient /= length;
    }
    return Eigen::Vector3f(static_cast<float>(gradient[0]), static_cast<float>(gradient[1]),
                           static_cast<float>(gradient[2]));
  }

  /// World-space position of an index-space point.
  template <typename MapT>
  static Eigen::Vector3f worldPosition(const MapT& map, const openvdb::Vec3d& indexPosition) {
    const openvdb::Vec3d world = map.applyMap(indexPosition);
    return Eigen::Vector3f(static_cast<float>(world[0]), static_cast<float>(world[1]),
                           static_cast<float>(world[2]));
  }

  /// Local index-space position of the vertex on the edge from (x, y, z) along `axis`, and its
  /// parameter t along the edge.
  openvdb::Vec3d localEdgePoint(const Region<ValueT>& region, int x, int y, int z, int axis,
                                double& t) const {
    const int start = Region<ValueT>::index(x, y, z);
    t = edgeParameter(region[start], region[start + Region<ValueT>::kStride[axis]]);
    openvdb::Vec3d point(x, y, z);
    point[axis] += t;
    return point;
  }

  /// Writes the position (and normal) of the vertex on the edge from (x, y, z) along `axis`.
  template <typename MapT>
  void writeEdgeVertex(const MapT& map, const Region<ValueT>& region,
                       const openvdb::Vec3d& originIndex, int x, int y, int z, int axis,
                       TriangleMesh::Index vertex) {
    double t = 0.0;
    const openvdb::Vec3d indexPosition = originIndex + localEdgePoint(region, x, y, z, axis, t);
    mesh_.positions[vertex] = worldPosition(map, indexPosition);
    if (!options_.computeNormals) return;
    const int start = Region<ValueT>::index(x, y, z);
    const int end = start + Region<ValueT>::kStride[axis];
    const openvdb::Vec3d gradient = (1.0 - t) * region.gradient(start) + t * region.gradient(end);
    const double sign = region[end] > region[start] ? 1.0 : -1.0;
    mesh_.normals[vertex] = worldNormal(map, gradient, indexPosition, axis, sign);
  }

  /// Pass 2: writes each block's vertices and triangles into its output ranges.
  template <typename MapT>
  void meshBlocks(const tbb::blocked_range<std::size_t>& range, const MapT& map) {
    auto accessor = grid_.getConstAccessor();
    NeighborValues<ValueT> neighborValues;
    auto region = std::make_unique<Region<ValueT>>();
    const auto& cellEdgeOffsets = cellEdgeKeyOffsets();
    std::vector<TriangleMesh::Index> vertexOfEdge(kEdgeKeyCount);
    const bool normals = options_.computeNormals;
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      const BlockCounts& counts = counts_[b];
      if (!counts.crossed) continue;
      const CornerRows& rows = counts.crossed->rows;
      const Ownership& ownership = ownerships_[counts.ownership];
      loadValues(b, accessor, !normals, neighborValues);
      region->gather(neighborValues, normals);
      const Coord origin = blocks_.origins[b];
      const openvdb::Vec3d originIndex(origin.x(), origin.y(), origin.z());
      auto nextVertex = static_cast<TriangleMesh::Index>(vertexBase_[b]);
      for (int x = 0; x <= kBlockSize; ++x) {
        for (int y = 0; y <= kBlockSize; ++y) {
          std::uint32_t crossed = crossedEdgesOfRow(rows, x, y);
          const std::uint32_t owned = counts.crossed->owned[x * kCornerSpan + y];
          const int rowKey = edgeKey(x, y, 0, 0);
          while (crossed != 0) {
            const int bit = __builtin_ctz(crossed);
            crossed &= crossed - 1;
            const int z = bit / 3, axis = bit - 3 * z;
            if ((owned >> bit) & 1u) {
              const TriangleMesh::Index vertex = nextVertex++;
              writeEdgeVertex(map, *region, originIndex, x, y, z, axis, vertex);
              vertexOfEdge[rowKey + bit] = vertex;
            } else {
              const std::array<int, 3> p{x, y, z};
              const auto [axisB, axisC] = otherAxes(axis);
              const int slot =
                  ownership
                      .ownerSlot[9 * axis + 3 * boundaryClass(p[axisB]) + boundaryClass(p[axisC])];
              vertexOfEdge[rowKey + bit] = lookUpVertex(b, slot, x, y, z, axis);
            }
          }
        }
      }

      std::size_t nextTriangle = triangleBase_[b];
      const auto regionValues = [&]() -> const Region<ValueT>& { return *region; };
      forEachCrossedCell(rows, [&](int x, int y, int z, int caseIndex) {
        const auto& cell = cellTriangulation(x, y, z, caseIndex, regionValues);
        const int cellKey = edgeKey(x, y, z, 0);
        TriangleMesh::Index center = 0;
        if (cell.centerEdges) {
          center = nextVertex++;
          writeCenterVertex(map, *region, originIndex, x, y, z, cell.centerEdges, center);
        }
        const auto vertexAt = [&](int edge) {
          return edge == detail::kCellCenter ? center
                                             : vertexOfEdge[cellKey + cellEdgeOffsets[edge]];
        };
        for (int i = 0; i < cell.triangleCount; ++i) {
          mesh_.triangles[nextTriangle++] = {vertexAt(cell.edges[3 * i]),
                                             vertexAt(cell.edges[3 * i + 1]),
                                             vertexAt(cell.edges[3 * i + 2])};
        }
      });
    }
  }

  /// The vertex of an edge numbered by the neighbour block in `ownerSlot`: its rank among that
  /// block's owned edges.
  TriangleMesh::Index lookUpVertex(std::size_t block, int ownerSlot, int x, int y, int z,
                                   int axis) const {
    const int ox = ownerSlot / 9 - 1, oy = (ownerSlot / 3) % 3 - 1, oz = ownerSlot % 3 - 1;
    const std::int32_t owner = ownerSlot >= 0 ? blocks_.neighbors[block][ownerSlot] : -1;
    const CrossedBlock* edges = owner >= 0 ? counts_[owner].crossed.get() : nullptr;
    const int row = (x - ox * kBlockSize) * kCornerSpan + (y - oy * kBlockSize);
    const int bit = 3 * (z - oz * kBlockSize) + axis;
    if (!edges || ((edges->owned[row] >> bit) & 1u) == 0) {
      throw RuntimeFailure("internal error in marching cubes: a shared edge has no vertex");
    }
    const std::uint32_t before = edges->owned[row] & ((1u << bit) - 1u);
    return static_cast<TriangleMesh::Index>(vertexBase_[owner] + edges->before[row] +
                                            static_cast<unsigned>(bitCount(before)));
  }

  /// Places a cell's centre vertex at the mean of its contour's edge vertices; its normal is the
  /// gradient of the cell's trilinear interpolant there.
  template <typename MapT>
  void writeCenterVertex(const MapT& map, const Region<ValueT>& region,
                         const openvdb::Vec3d& originIndex, int x, int y, int z,
                         std::uint16_t edges, TriangleMesh::Index vertex) {
    openvdb::Vec3d sum(0.0);
    int count = 0;
    for (int edge = 0; edge < detail::kCubeEdges; ++edge) {
      if (((edges >> edge) & 1) == 0) continue;
      const auto start = detail::cornerOffset(detail::edgeStartCorner(edge));
      double t = 0.0;
      sum += localEdgePoint(region, x + start[0], y + start[1], z + start[2],
                            detail::edgeAxis(edge), t);
      ++count;
    }
    const openvdb::Vec3d local = sum / static_cast<double>(count);
    mesh_.positions[vertex] = worldPosition(map, originIndex + local);
    if (!options_.computeNormals) return;
    const double u = local[0] - x, v = local[1] - y, w = local[2] - z;
    const auto f = [&](int dx, int dy, int dz) {
      return static_cast<double>(region(x + dx, y + dy, z + dz));
    };
    const auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
    const openvdb::Vec3d gradient(
        lerp(lerp(f(1, 0, 0) - f(0, 0, 0), f(1, 1, 0) - f(0, 1, 0), v),
             lerp(f(1, 0, 1) - f(0, 0, 1), f(1, 1, 1) - f(0, 1, 1), v), w),
        lerp(lerp(f(0, 1, 0) - f(0, 0, 0), f(1, 1, 0) - f(1, 0, 0), u),
             lerp(f(0, 1, 1) - f(0, 0, 1), f(1, 1, 1) - f(1, 0, 1), u), w),
        lerp(lerp(f(0, 0, 1) - f(0, 0, 0), f(1, 0, 1) - f(1, 0, 0), u),
             lerp(f(0, 1, 1) - f(0, 1, 0), f(1, 1, 1) - f(1, 1, 0), u), v));
    mesh_.normals[vertex] = worldNormal(map, gradient, originIndex + local, 2, 1.0);
  }

  const GridT& grid_;
  const IsoSurfaceOptions& options_;
  const ProgressCallback& progress_;
  const CubeTables& tables_;
  std::array<const detail::CellTriangulation*, 256> plainCells_{};  ///< cases without ambiguity
  BlockSet<typename GridT::TreeType::LeafNodeType> blocks_;
  std::vector<const ValueT*> leafData_;  ///< per block: its leaf's values, or null
  std::vector<ValueT> fillValue_;        ///< per block without a leaf: its tile/background value
  std::vector<InsideWords> inside_;      ///< per block: inside flags of its values
  std::vector<std::uint8_t> side_;       ///< per block: Side of its values
  std::vector<std::uint32_t> ownershipMasks_;  ///< distinct neighbour masks, sorted
  std::vector<Ownership> ownerships_;          ///< the ownership rule of each of them
  std::vector<BlockCounts> counts_;
  std::vector<std::uint64_t> vertexBase_, triangleBase_;
  TriangleMesh mesh_;
};

template <typename GridT>
TriangleMesh extract(const GridT& grid, const IsoSurfaceOptions& options,
                     const ProgressCallback& progress) {
  if (grid.tree().hasActiveTiles()) {
    const typename GridT::Ptr voxelized = grid.deepCopy();
    voxelized->tree().voxelizeActiveTiles();
    return Extractor<GridT>(*voxelized, options, progress).run();
  }
  return Extractor<GridT>(grid, options, progress).run();
}

}  // namespace

TriangleMesh extractIsoSurface(const openvdb::FloatGrid& grid, const IsoSurfaceOptions& options,
                               const ProgressCallback& progress) {
  return extract(grid, options, progress);
}

TriangleMesh extractIsoSurface(const openvdb::DoubleGrid& grid, const IsoSurfaceOptions& options,
                               const ProgressCallback& progress) {
  return extract(grid, options, progress);
}

TriangleMesh extractIsoSurface(const openvdb::GridBase& grid, const IsoSurfaceOptions& options,
                               const ProgressCallback& progress) {
  if (const auto* floatGrid = dynamic_cast<const openvdb::FloatGrid*>(&grid)) {
    return extractIsoSurface(*floatGrid, options, progress);
  }
  if (const auto* doubleGrid = dynamic_cast<const openvdb::DoubleGrid*>(&grid)) {
    return extractIsoSurface(*doubleGrid, options, progress);
  }
  throw InputError("grid '" + grid.getName() + "' holds " + grid.valueType() +
                   " values; iso-surfaces need a float or double grid");
}

}  // namespace d2vdb
