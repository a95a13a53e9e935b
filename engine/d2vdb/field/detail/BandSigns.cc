// The exact-sign pass over a mesh level set's band: closest-feature sides near the surface,
// winding numbers for undecided voxels and for far groups, then the rewrite and flood fill.
#include "d2vdb/field/detail/BandSigns.h"

#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>
#include <vector>

#include "d2vdb/core/detail/DisjointSets.h"
#include "d2vdb/field/detail/HoleCrossings.h"
#include "d2vdb/field/detail/RayWinding.h"
#include "d2vdb/mesh/TriangleClosestPoint.h"

namespace d2vdb::detail {
namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;
using IndexLeaf = openvdb::Int32Tree::LeafNodeType;
constexpr openvdb::Index kVoxels = FloatLeaf::SIZE;
constexpr int kDim = FloatLeaf::DIM;

/// Squared distance (voxels^2) below which a voxel counts as near: OpenVDB's closest triangle is
/// exact there (it is for squared distances up to 0.75; 0.7 keeps rounding far away).
constexpr double kNearLimit2 = 0.7;
/// A voxel that is not near is at least this far from the mesh (voxels): sqrt(0.7) less the
/// float rounding of OpenVDB's squared distances (relative 1.2e-7, taken as 2e-5).
const double kFarBound = std::sqrt(0.7 * (1.0 - 2e-5));
/// A near voxel at least this far from the mesh shares its side with a far 6-neighbour.
const double kLinkDistance = 1.0 - kFarBound + 1e-9;
/// The clearance stored for far voxels: kFarBound rounded down.
const float kFarClearance = static_cast<float>(kFarBound * (1.0 - 1e-6));
/// Voxel centres this close to the mesh (voxels) keep OpenVDB's sign: either side is right.
constexpr double kOnSurface = 1e-6;

// Voxel state bits.
constexpr std::uint8_t kActive = 1;
constexpr std::uint8_t kNear = 2;      ///< within sqrt(0.7) voxel of M + S
constexpr std::uint8_t kKnown = 4;     ///< its W (integer winding number of M + S) is known
constexpr std::uint8_t kLinkable = 8;  ///< near, and far enough to link with far neighbours
constexpr std::uint8_t kFinal = 16;    ///< inside/outside decided
constexpr std::uint8_t kInside = 32;   ///< (with kFinal) inside
constexpr std::uint8_t kKeep = 64;     ///< on M: keeps OpenVDB's sign
/// A near voxel far enough from M + S to pass its W on to the far voxels beside it.
constexpr std::uint8_t kSeed = kActive | kNear | kKnown | kLinkable;
/// W of a group whose seeds disagree: each of its voxels gets its own winding number.
constexpr std::int16_t kPerVoxel = std::numeric_limits<std::int16_t>::min();

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint16_t kNoLabel = std::numeric_limits<std::uint16_t>::max();

using States = std::array<std::uint8_t, kVoxels>;
using Windings = std::array<std::int16_t, kVoxels>;
/// Per voxel a lower bound of its distance to M + S (voxels), rounded down: exact distances near
/// the surface, kFarBound beyond.
using Clearances = std::array<float, kVoxels>;

/// Two 6-neighbours are linked when their clearances add up to more than this: a voxel, with
/// room for the rounding of the clearances.
constexpr double kLinkSum = 1.0 + 1e-6;

/// A clearance as stored: rounded down, so that it stays a lower bound.
float storedClearance(double distance) {
  return static_cast<float>(distance * (1.0 - 1e-6));
}

/// The per-voxel records of every leaf (in SignLeafTable order) the passes share.
struct VoxelData {
  std::vector<States> states;
  std::vector<Windings> windings;
  std::vector<Clearances> clearances;
};

openvdb::Index offsetOf(int x, int y, int z) {
  return static_cast<openvdb::Index>((x << (2 * FloatLeaf::LOG2DIM)) + (y << FloatLeaf::LOG2DIM) +
                                     z);
}

/// Offset of the voxel at `depth` along `axis` and (u, v) along the two others.
openvdb::Index faceOffset(int axis, int depth, int u, int v) {
  std::array<int, 3> c{};
  c[axis] = depth;
  c[(axis + 1) % 3] = u;
  c[(axis + 2) % 3] = v;
  return offsetOf(c[0], c[1], c[2]);
}

/// Leaves in tree order, with their six face neighbours and a coordinate lookup.
class SignLeafTable {
 public:
  explicit SignLeafTable(openvdb::FloatTree& tree) {
    leaves_.reserve(tree.leafCount());
    tree.getNodes(leaves_);
    sorted_.resize(leaves_.size());
    for (std::uint32_t i = 0; i < leaves_.size(); ++i) sorted_[i] = {leaves_[i]->origin(), i};
    std::sort(sorted_.begin(), sorted_.end(),
              [](const Entry& a, const Entry& b) { return a.origin < b.origin; });
    neighbors_.resize(leaves_.size());
    tbb::parallel_for(std::size_t{0}, leaves_.size(), [this](std::size_t i) {
      const openvdb::Coord origin = leaves_[i]->origin();
      for (int axis = 0; axis < 3; ++axis) {
        for (int direction = 0; direction < 2; ++direction) {
          openvdb::Coord other = origin;
          other[axis] += direction == 0 ? -kDim : kDim;
          neighbors_[i][2 * axis + direction] = find(other);
        }
      }
    });
  }

  std::size_t size() const { return leaves_.size(); }
  FloatLeaf& leaf(std::size_t i) const { return *leaves_[i]; }
  /// Neighbour across face 2 * axis + (0 for -, 1 for +), or kNone.
  std::uint32_t neighbor(std::size_t i, int face) const { return neighbors_[i][face]; }

  /// The leaf with this origin, or kNone.
  std::uint32_t find(const openvdb::Coord& origin) const {
    const auto found = std::lower_bound(
        sorted_.begin(), sorted_.end(), origin,
        [](const Entry& entry, const openvdb::Coord& key) { return entry.origin < key; });
    return found != sorted_.end() && found->origin == origin ? found->index : kNone;
  }

 private:
  struct Entry {
    openvdb::Coord origin;
    std::uint32_t index;
  };
  std::vector<FloatLeaf*> leaves_;
  std::vector<Entry> sorted_;
  std::vector<std::array<std::uint32_t, 6>> neighbors_;
};

/// The range of W over the known voxels linked to a group.
struct Seeds {
  std::int16_t low = std::numeric_limits<std::int16_t>::max();
  std::int16_t high = std::numeric_limits<std::int16_t>::min();
  bool empty() const { return low > high; }
  void add(std::int16_t w) {
    low = std::min(low, w);
    high = std::max(high, w);
  }
  void add(const Seeds& other) {
    low = std::min(low, other.low);
    high = std::max(high, other.high);
  }
};

/// Voxels of one leaf whose W is not known yet, grouped by links inside the leaf.
struct LocalGroups {
  std::array<std::uint16_t, kVoxels> label;   ///< group of each grouped voxel, or kNoLabel
  std::vector<std::uint16_t> representative;  ///< voxel (offset) of each group farthest out
  std::vector<float> reach;                   ///< |value| of that voxel (world units)
  std::vector<Seeds> seeds;                   ///< W of the linked known neighbours
};

/// A leaf's states, W and clearances with a one-voxel shell from its face neighbours, indexed
/// (x + 1) * 100 + (y + 1) * 10 + (z + 1), so that 6-neighbours are +-100, +-10, +-1 away.
struct PaddedBlock {
  static constexpr int kSide = kDim + 2;
  static constexpr int index(int x, int y, int z) {
    return ((x + 1) * kSide + (y + 1)) * kSide + (z + 1);
  }
  std::array<std::uint8_t, kSide * kSide * kSide> state{};
  std::array<std::int16_t, kSide * kSide * kSide> winding{};
  std::array<float, kSide * kSide * kSide> clearance{};

  PaddedBlock(const SignLeafTable& table, const VoxelData& data, std::size_t i) {
    for (int x = 0; x < kDim; ++x)
      for (int y = 0; y < kDim; ++y)
        for (int z = 0; z < kDim; ++z) copy(index(x, y, z), data, i, offsetOf(x, y, z));
    for (int axis = 0; axis < 3; ++axis) {
      for (int direction = 0; direction < 2; ++direction) {
        const std::uint32_t j = table.neighbor(i, 2 * axis + direction);
        if (j == kNone) continue;
        const int depth = direction == 0 ? kDim - 1 : 0;  // the neighbour's touching layer
        const int shell = direction == 0 ? -1 : kDim;
        for (int u = 0; u < kDim; ++u) {
          for (int v = 0; v < kDim; ++v) {
            std::array<int, 3> c{};
            c[axis] = shell;
            c[(axis + 1) % 3] = u;
            c[(axis + 2) % 3] = v;
            copy(index(c[0], c[1], c[2]), data, j, faceOffset(axis, depth, u, v));
          }
        }
      }
    }
  }

 private:
  void copy(int b, const VoxelData& data, std::size_t leaf, openvdb::Index o) {
    state[b] = data.states[leaf][o];
    winding[b] = data.windings[leaf][o];
    clearance[b] = data.clearances[leaf][o];
  }
};

/// An active voxel whose W is still to be found (not known, not final): it joins a group.
bool isGroupable(std::uint8_t s) {
  return (s & (kActive | kKnown | kFinal)) == kActive;
}

/// An active voxel whose W is known: it passes W on to the groups it is linked to.
bool isKnown(std::uint8_t s) {
  return (s & (kActive | kKnown)) == (kActive | kKnown);
}

/// Two 6-neighbours (one voxel apart) whose clearances add up to more than a voxel: no point of
/// M + S lies on the segment between them (it would be nearer to both), so they share W.
bool linked(float a, float b) {
  return double(a) + double(b) > kLinkSum;
}

LocalGroups groupVoxels(const SignLeafTable& table, const VoxelData& data, std::size_t i) {
  LocalGroups groups;
  groups.label.fill(kNoLabel);
  const States& state = data.states[i];
  const Clearances& clearance = data.clearances[i];
  bool anyGroupable = false;
  for (const std::uint8_t s : state) anyGroupable = anyGroupable || isGroupable(s);
  if (!anyGroupable) return groups;
  const PaddedBlock block(table, data, i);
  std::array<std::uint16_t, kVoxels> parent;
  const auto find = [&parent](std::uint16_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  const auto unite = [&](openvdb::Index a, openvdb::Index b) {
    if (!isGroupable(state[b]) || !linked(clearance[a], clearance[b])) return;
    const std::uint16_t ra = find(static_cast<std::uint16_t>(a));
    const std::uint16_t rb = find(static_cast<std::uint16_t>(b));
    if (ra < rb)
      parent[rb] = ra;
    else if (rb < ra)
      parent[ra] = rb;
  };
  constexpr int kStepX = PaddedBlock::kSide * PaddedBlock::kSide;
  constexpr int kStepY = PaddedBlock::kSide;
  for (int x = 0; x < kDim; ++x) {
    for (int y = 0; y < kDim; ++y) {
      for (int z = 0; z < kDim; ++z) {
        const openvdb::Index o = offsetOf(x, y, z);
        parent[o] = static_cast<std::uint16_t>(o);
        if (!isGroupable(state[o])) continue;
        if (x > 0) unite(o, o - kDim * kDim);
        if (y > 0) unite(o, o - kDim);
        if (z > 0) unite(o, o - 1);
      }
    }
  }
  const FloatLeaf& leaf = table.leaf(i);
  for (int x = 0; x < kDim; ++x) {
    for (int y = 0; y < kDim; ++y) {
      for (int z = 0; z < kDim; ++z) {
        const openvdb::Index o = offsetOf(x, y, z);
        if (!isGroupable(state[o])) continue;
        const std::uint16_t root = find(static_cast<std::uint16_t>(o));
        const float reach = std::abs(leaf.getValue(o));
        if (groups.label[root] == kNoLabel) {
          groups.label[root] = static_cast<std::uint16_t>(groups.representative.size());
          groups.representative.push_back(static_cast<std::uint16_t>(o));
          groups.reach.push_back(reach);
          groups.seeds.emplace_back();
        }
        const std::uint16_t label = groups.label[root];
        groups.label[o] = label;
        // The voxel farthest from the surface (first in offset order among equals) represents
        // the group: its winding number is the cheapest to certify.
        if (reach > groups.reach[label]) {
          groups.reach[label] = reach;
          groups.representative[label] = static_cast<std::uint16_t>(o);
        }
        const int b = PaddedBlock::index(x, y, z);
        for (const int step : {-kStepX, kStepX, -kStepY, kStepY, -1, 1}) {
          if (isKnown(block.state[b + step]) && linked(clearance[o], block.clearance[b + step])) {
            groups.seeds[label].add(block.winding[b + step]);
          }
        }
      }
    }
  }
  return groups;
}

/// One bit per voxel of a leaf: word x, bit 8 y + z (the leaf's own offset order).
using Mask = std::array<std::uint64_t, kDim>;
constexpr std::uint64_t kLowZ = 0x0101010101010101ull;  // z = 0 in every row
constexpr std::uint64_t kHighZ = kLowZ << 7;            // z = 7
constexpr std::uint64_t kLowY = 0xffull;                // y = 0
constexpr int kHighYShift = 8 * (kDim - 1);             // y = 7 starts at this bit

bool isEmpty(const Mask& m) {
  std::uint64_t any = 0;
  for (const std::uint64_t w : m) any |= w;
  return any == 0;
}

/// The voxels of leaf i that are 6-neighbours of a set voxel of masks (in leaf i or across one
/// of its faces).
Mask neighborsOf(const std::vector<Mask>& masks, const SignLeafTable& table, std::size_t i) {
  const Mask& m = masks[i];
  Mask out{};
  for (int x = 0; x < kDim; ++x) {
    const std::uint64_t w = m[x];
    std::uint64_t n = ((w << 1) & ~kLowZ) | ((w >> 1) & ~kHighZ) | (w << 8) | (w >> 8);
    if (x > 0) n |= m[x - 1];
    if (x < kDim - 1) n |= m[x + 1];
    out[x] = n;
  }
  if (const std::uint32_t j = table.neighbor(i, 0); j != kNone) out[0] |= masks[j][kDim - 1];
  if (const std::uint32_t j = table.neighbor(i, 1); j != kNone) out[kDim - 1] |= masks[j][0];
  for (int x = 0; x < kDim; ++x) {
    if (const std::uint32_t j = table.neighbor(i, 2); j != kNone) {
      out[x] |= (masks[j][x] >> kHighYShift) & kLowY;
    }
    if (const std::uint32_t j = table.neighbor(i, 3); j != kNone) {
      out[x] |= (masks[j][x] & kLowY) << kHighYShift;
    }
    if (const std::uint32_t j = table.neighbor(i, 4); j != kNone) {
      out[x] |= (masks[j][x] & kHighZ) >> 7;
    }
    if (const std::uint32_t j = table.neighbor(i, 5); j != kNone) {
      out[x] |= (masks[j][x] & kLowZ) << 7;
    }
  }
  return out;
}

/// The masks dilated by one voxel along `axis` (0 x, 1 y, 2 z), across the leaves' faces.
std::vector<Mask> dilateAlong(const std::vector<Mask>& masks, const SignLeafTable& table,
                              int axis) {
  std::vector<Mask> out(masks.size());
  tbb::parallel_for(std::size_t{0}, masks.size(), [&](std::size_t i) {
    const Mask& m = masks[i];
    Mask& d = out[i];
    const std::uint32_t low = table.neighbor(i, 2 * axis);
    const std::uint32_t high = table.neighbor(i, 2 * axis + 1);
    for (int x = 0; x < kDim; ++x) {
      const std::uint64_t w = m[x];
      if (axis == 0) {
        d[x] = w | (x > 0 ? m[x - 1] : (low != kNone ? masks[low][kDim - 1] : 0)) |
               (x < kDim - 1 ? m[x + 1] : (high != kNone ? masks[high][0] : 0));
      } else if (axis == 1) {
        d[x] = w | (w << 8) | (w >> 8);
        if (low != kNone) d[x] |= (masks[low][x] >> kHighYShift) & kLowY;
        if (high != kNone) d[x] |= (masks[high][x] & kLowY) << kHighYShift;
      } else {
        d[x] = w | ((w << 1) & ~kLowZ) | ((w >> 1) & ~kHighZ);
        if (low != kNone) d[x] |= (masks[low][x] & kHighZ) >> 7;
        if (high != kNone) d[x] |= (masks[high][x] & kLowZ) << 7;
      }
    }
  });
  return out;
}

/// What the near pass of one leaf found (one bit per voxel in the masks).
struct LeafSummary {
  Mask far{};          ///< active voxels not near M + S
  Mask farInside{};    ///< far voxels OpenVDB put inside
  Mask seedInside{};   ///< near voxels linkable to far neighbours, inside (no caps)
  Mask seedOutside{};  ///< ... outside
  std::vector<openvdb::Index> undecided;  ///< near voxels whose W is not known yet
  std::vector<openvdb::Coord> flipped;    ///< voxels decided against OpenVDB's sign
  std::size_t near = 0;
  std::size_t queries = 0;
};

/// Grows `reached` inside one leaf along 6-adjacency through the voxels of `far`, until it stops.
void growWithinLeaf(Mask& reached, const Mask& far) {
  for (bool growing = true; growing;) {
    Mask n{};
    for (int x = 0; x < kDim; ++x) {
      const std::uint64_t w = reached[x];
      n[x] = ((w << 1) & ~kLowZ) | ((w >> 1) & ~kHighZ) | (w << 8) | (w >> 8);
      if (x > 0) n[x] |= reached[x - 1];
      if (x < kDim - 1) n[x] |= reached[x + 1];
    }
    growing = false;
    for (int x = 0; x < kDim; ++x) {
      const std::uint64_t grown = reached[x] | (n[x] & far[x]);
      growing = growing || grown != reached[x];
      reached[x] = grown;
    }
  }
}

/// One round of the reachability search for leaf i: what its neighbours reached in the previous
/// round, then grown inside the leaf, into `next`. True when leaf i reached more than before.
bool reachRound(const SignLeafTable& table, const std::vector<Mask>& far,
                const std::vector<Mask>& reached, std::size_t i, Mask& next) {
  Mask r = reached[i];
  if (isEmpty(far[i])) {
    next = r;
    return false;
  }
  const Mask across = neighborsOf(reached, table, i);
  for (int x = 0; x < kDim; ++x) r[x] |= across[x] & far[i][x];
  growWithinLeaf(r, far[i]);
  bool more = false;
  for (int x = 0; x < kDim; ++x) more = more || r[x] != reached[i][x];
  next = r;
  return more;
}

/// Whether every voxel of `far` is reachable through far-far links from a far voxel next to one
/// of `seeds`: grown in rounds (each leaf in parallel from the previous round's state, so the
/// result does not depend on the schedule) until nothing changes.
bool allFarReachable(const SignLeafTable& table, const std::vector<Mask>& far,
                     const std::vector<Mask>& seeds) {
  const std::size_t leafCount = table.size();
  std::vector<Mask> reached(leafCount);
  tbb::parallel_for(std::size_t{0}, leafCount, [&](std::size_t i) {
    const Mask n = neighborsOf(seeds, table, i);
    for (int x = 0; x < kDim; ++x) reached[i][x] = n[x] & far[i][x];
  });
  std::vector<Mask> next(leafCount);
  for (bool changed = true; changed;) {
    std::atomic<bool> grew{false};
    tbb::parallel_for(std::size_t{0}, leafCount, [&](std::size_t i) {
      if (reachRound(table, far, reached, i, next[i])) grew.store(true, std::memory_order_relaxed);
    });
    reached.swap(next);
    changed = grew.load();
  }
  for (std::size_t i = 0; i < leafCount; ++i) {
    for (int x = 0; x < kDim; ++x) {
      if ((far[i][x] & ~reached[i][x]) != 0) return false;
    }
  }
  return true;
}

/// Without caps, inside is W >= 1 and constant wherever W is. Checks, with bit operations on
/// every leaf, that OpenVDB's sign is already right on every far voxel: it agrees across every
/// far-far link and with every linked near voxel, and every far voxel is reachable from a linked
/// near voxel through far-far links. Then each group of far voxels has one sign, which is its
/// seeds' W. False when a check fails (the caller then groups the far voxels explicitly).
bool farSignsVerified(const SignLeafTable& table, const std::vector<LeafSummary>& summaries) {
  const std::size_t leafCount = table.size();
  std::vector<Mask> far(leafCount), farIn(leafCount), inSide(leafCount), outSide(leafCount),
      seeds(leafCount);
  tbb::parallel_for(std::size_t{0}, leafCount, [&](std::size_t i) {
    const LeafSummary& leaf = summaries[i];
    far[i] = leaf.far;
    farIn[i] = leaf.farInside;
    for (int x = 0; x < kDim; ++x) {
      inSide[i][x] = leaf.seedInside[x] | leaf.farInside[x];
      outSide[i][x] = leaf.seedOutside[x] | (leaf.far[x] & ~leaf.farInside[x]);
      seeds[i][x] = leaf.seedInside[x] | leaf.seedOutside[x];
    }
  });
  // Sign consistency across far-far and near-far links.
  std::atomic<bool> consistent{true};
  tbb::parallel_for(std::size_t{0}, leafCount, [&](std::size_t i) {
    const Mask nearInside = neighborsOf(inSide, table, i);
    const Mask nearOutside = neighborsOf(outSide, table, i);
    std::uint64_t clash = 0;
    for (int x = 0; x < kDim; ++x) {
      clash |= (nearInside[x] & far[i][x] & ~farIn[i][x]) | (nearOutside[x] & farIn[i][x]);
    }
    if (clash != 0) consistent.store(false, std::memory_order_relaxed);
  });
  if (!consistent.load()) return false;
  return allFarReachable(table, far, seeds);
}

/// A lower bound of the distance from the box [low, high] to the triangles of `bvh` (its boxes
/// and those of single triangles); stops early with a value at most `limit` once one is nearer
/// than `limit`.
double capClearance(const TriangleBvh& bvh, const std::vector<Eigen::Vector3d>& points,
                    const std::vector<TriangleIndices>& triangles, const Eigen::Vector3d& low,
                    const Eigen::Vector3d& high, double limit) {
  const auto gap = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return (a - high).cwiseMax(low - b).cwiseMax(Eigen::Vector3d::Zero()).norm();
  };
  double nearest = std::numeric_limits<double>::infinity();
  walkDepthFirst(bvh, [&](std::uint32_t, const TriangleBvh::Node& node) {
    if (gap(node.low, node.high) >= nearest) return BvhStep::kSkip;
    if (!node.isLeaf()) return BvhStep::kChildren;
    for (std::uint32_t k = node.begin; k < node.end; ++k) {
      const auto [a, b, c] = cornersOf(points, triangles[bvh.order()[k]]);
      nearest = std::min(nearest, gap(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)));
    }
    return nearest <= limit ? BvhStep::kStop : BvhStep::kSkip;
  });
  return nearest;
}

/// Voxel coordinates as a point in index space.
Eigen::Vector3d pointOf(const openvdb::Coord& ijk) {
  return Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z());
}

/// The far voxels of the whole band in groups: each leaf's local groups, numbered consecutively
/// (leaf i's from base[i]), joined across the leaves' faces in `sets`.
struct FarGroups {
  std::vector<LocalGroups> local;
  std::vector<std::uint32_t> base;  ///< leafCount + 1 entries; the last is the number of groups
  DisjointSets<std::uint32_t> sets;
};

FarGroups joinFarGroups(const SignLeafTable& table, const VoxelData& data) {
  const std::size_t leafCount = table.size();
  std::vector<LocalGroups> local(leafCount);
  tbb::parallel_for(std::size_t{0}, leafCount,
                    [&](std::size_t i) { local[i] = groupVoxels(table, data, i); });
  std::vector<std::uint32_t> base(leafCount + 1, 0);
  for (std::size_t i = 0; i < leafCount; ++i) {
    base[i + 1] = base[i] + static_cast<std::uint32_t>(local[i].representative.size());
  }
  const std::uint32_t total = base[leafCount];
  FarGroups groups{std::move(local), std::move(base), DisjointSets<std::uint32_t>(total)};
  for (std::size_t i = 0; i < leafCount; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      const std::uint32_t j = table.neighbor(i, 2 * axis + 1);
      if (j == kNone) continue;
      for (int u = 0; u < kDim; ++u) {
        for (int v = 0; v < kDim; ++v) {
          const openvdb::Index oi = faceOffset(axis, kDim - 1, u, v);
          const openvdb::Index oj = faceOffset(axis, 0, u, v);
          const std::uint16_t a = groups.local[i].label[oi];
          const std::uint16_t b = groups.local[j].label[oj];
          if (a != kNoLabel && b != kNoLabel &&
              linked(data.clearances[i][oi], data.clearances[j][oj])) {
            groups.sets.unite(groups.base[i] + a, groups.base[j] + b);
          }
        }
      }
    }
  }
  return groups;
}

/// One run of correctBandSigns() over a band with at least one leaf: the per-voxel states and W
/// and the per-leaf summaries its phases fill in, in this order: near voxels (closest feature,
/// then their own winding numbers), far voxels (the bit check, else groups), then the rewrite of
/// the flipped voxels and their neighbours.
class BandSignCorrection {
 public:
  BandSignCorrection(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closest,
                     const BandSignInputs& inputs, const SignLeafTable& table)
      : grid_(grid),
        table_(table),
        mesh_(*inputs.mesh),
        closed_(*inputs.closed),
        caps_(inputs.caps),
        sides_(inputs.sides),
        progress_(inputs.progress),
        decideBySides_(inputs.embedded && inputs.sides && !inputs.sides->empty()),
        leafCount_(table.size()),
        voxelSize_(grid.voxelSize()[0]),
        // Near voxels have values up to sqrt(0.7) voxel, or sqrt(0.75) where meshToVolume pushed
        // a voxel with no inside neighbour out of the surface layer.
        nearValueLimit_(static_cast<float>(0.867 * voxelSize_)),
        meshTriangles_(static_cast<std::int64_t>(mesh_.meshTriangleCount)),
        closestLeaves_(leafCount_),
        data_{std::vector<States>(leafCount_), std::vector<Windings>(leafCount_),
              std::vector<Clearances>(leafCount_)},
        summaries_(leafCount_),
        capsNear_(caps_ ? leafCount_ : 0, 1),
        capBound_(caps_ ? leafCount_ : 0, 0.0) {
    for (std::size_t i = 0; i < leafCount_; ++i) {
      closestLeaves_[i] = closest.tree().probeConstLeaf(table_.leaf(i).origin());
    }
  }

  BandSignReport run() {
    BandSignReport report;
    // Near voxels: exact closest point on M + S, then W from its side where that is decisive.
    // Without caps, inside is W >= 1 and is compared with OpenVDB's sign right away.
    forLeaves(0.0, 0.3, [this](std::size_t i) { classifyLeaf(i); });
    // Near voxels the closest feature did not decide (embedded M + S): their own winding number.
    forLeaves(0.3, 0.5, [this](std::size_t i) { settleUndecided(i); });
    // The other voxels. Without caps, with every near voxel decided, OpenVDB's sign is usually
    // right there, which bit operations can check; otherwise: groups, their seeds, one winding
    // number for a group without any.
    const bool farVerified = !caps_ && decideBySides_ && farSignsVerified(table_, summaries_);
    if (!farVerified) decideFarVoxels(report);
    reportProgress(0.95);
    for (const LeafSummary& summary : summaries_) {
      report.nearVoxels += summary.near;
      report.windingNumberQueries += summary.queries;
    }
    const std::vector<Mask> affected = affectedVoxels(report);
    if (report.correctedVoxels == 0) return report;
    rewrite(affected);
    const float background = grid_.background();
    openvdb::tools::signedFloodFillWithValues(grid_.tree(), background, -background);
    return report;
  }

 private:
  void reportProgress(double fraction) const {
    if (progress_) progress_(fraction);
  }

  /// Runs `body` on every leaf in parallel, in a fixed number of slices, reporting progress from
  /// `from` to `to` after each slice (leaves are independent, so slicing changes no result).
  template <typename Body>
  void forLeaves(double from, double to, const Body& body) const {
    constexpr std::size_t kSlices = 20;
    for (std::size_t slice = 0; slice < kSlices; ++slice) {
      const std::size_t begin = leafCount_ * slice / kSlices;
      const std::size_t end = leafCount_ * (slice + 1) / kSlices;
      tbb::parallel_for(begin, end, body);
      reportProgress(from + (to - from) * double(slice + 1) / kSlices);
    }
  }

  /// Closest point on M's recorded triangle t (index into mesh.triangles), or none.
  NearestTriangle closestOnMesh(std::int64_t t, const Eigen::Vector3d& p) const {
    NearestTriangle nearest;
    if (t < 0 || t >= meshTriangles_) return nearest;
    const TriangleIndices& tri = mesh_.triangles[static_cast<std::size_t>(t)];
    nearest.triangle = static_cast<std::uint32_t>(t);
    nearest.closest =
        closestPointOnTriangle(p, mesh_.points[tri[0]], mesh_.points[tri[1]], mesh_.points[tri[2]]);
    nearest.squaredDistance = (nearest.closest.point - p).squaredNorm();
    return nearest;
  }

  /// W of M + S at p, certified: by signed ray crossings (M + S is watertight), else, when every
  /// ray met a predicate in doubt, hierarchically.
  std::int16_t windingAt(const Eigen::Vector3d& p) const {
    const std::optional<long> crossings =
        rayWindingNumber(closed_.hierarchy(), mesh_.points, mesh_.triangles, p);
    const long w = crossings ? *crossings : closed_.integerValue(p);
    return static_cast<std::int16_t>(std::clamp<long>(w, -32000, 32000));
  }

  /// Records W at a near voxel; without caps also its final side, a flip, and a seed bit.
  void settle(std::size_t i, openvdb::Index o, std::int16_t w, float value) {
    std::uint8_t& s = data_.states[i][o];
    data_.windings[i][o] = w;
    s |= kKnown;
    if (caps_) return;
    const bool inside = w >= 1;
    s |= kFinal | (inside ? kInside : 0);
    LeafSummary& summary = summaries_[i];
    if (inside != (value < 0.0f)) {
      summary.flipped.push_back(table_.leaf(i).offsetToGlobalCoord(o));
    }
    if ((s & kSeed) == kSeed) {
      (inside ? summary.seedInside : summary.seedOutside)[o >> 6] |= std::uint64_t{1} << (o & 63);
    }
  }

  /// The near pass over the active voxels of leaf i.
  void classifyLeaf(std::size_t i) {
    States& state = data_.states[i];
    state.fill(0);
    data_.clearances[i].fill(0.0f);
    if (caps_) boundCaps(i);
    LeafSummary& summary = summaries_[i];
    const IndexLeaf* indices = closestLeaves_[i];
    for (auto voxel = table_.leaf(i).cbeginValueOn(); voxel; ++voxel) {
      classifyVoxel(i, voxel.pos(), *voxel, voxel.getCoord(), indices, state, summary);
    }
  }

  /// Voxel o of leaf i (value `value`, coordinates ijk): on M, far, or near M + S.
  void classifyVoxel(std::size_t i, openvdb::Index o, float value, const openvdb::Coord& ijk,
                     const IndexLeaf* indices, States& state, LeafSummary& summary) {
    const Eigen::Vector3d p = pointOf(ijk);
    // meshToVolume's values (before renormalisation) are distances to actual triangles, so a
    // larger one proves the voxel is not near M without looking at the triangle.
    NearestTriangle nearest;
    if (std::abs(value) <= nearValueLimit_) {
      nearest = closestOnMesh(indices ? indices->getValue(o) : -1, p);
    }
    const bool nearMesh = nearest.squaredDistance <= kNearLimit2;
    if (nearMesh && std::sqrt(nearest.squaredDistance) <= kOnSurface) {
      state[o] = kActive | kNear | kFinal | kKeep | (value < 0.0f ? kInside : 0);
      ++summary.near;
      return;  // clearance 0
    }
    if (!nearMesh) nearest = NearestTriangle{};
    if (caps_ && capsNear_[i]) preferNearerCap(nearMesh, p, nearest);
    if (!(nearest.squaredDistance <= kNearLimit2)) {
      state[o] = kActive;
      data_.clearances[i][o] = kFarClearance;
      const std::uint64_t bit = std::uint64_t{1} << (o & 63);
      summary.far[o >> 6] |= bit;
      if (value < 0.0f) summary.farInside[o >> 6] |= bit;
      return;
    }
    classifyNearVoxel(i, o, value, ijk, p, nearest, state[o], summary);
  }

  /// What the caps can do at the voxels of leaf i, from the box of their centres: whether a cap
  /// may lie within the near zone of one (capsNear_), and a bound on |w_S| over them (capBound_).
  void boundCaps(std::size_t i) {
    const openvdb::Coord origin = table_.leaf(i).origin();
    const Eigen::Vector3d low = pointOf(origin);
    const Eigen::Vector3d high = low + Eigen::Vector3d::Constant(kDim - 1);
    capsNear_[i] = capClearance(caps_->hierarchy(), mesh_.points, mesh_.caps, low, high,
                                std::sqrt(kNearLimit2)) <= std::sqrt(kNearLimit2);
    capBound_[i] = caps_->boundOverBox(low, high, 0.5);
  }

  /// Replaces `nearest` (on M, or none) by the nearest cap triangle when that is the closest
  /// feature of M + S within the near zone.
  void preferNearerCap(bool nearMesh, const Eigen::Vector3d& p, NearestTriangle& nearest) const {
    NearestTriangle onCap = nearestTriangle(caps_->hierarchy(), mesh_.points, mesh_.caps, p);
    // Off M's near zone the distance to M is only known to exceed kFarBound: a cap point is then
    // the closest point of M + S only if it is nearer than that.
    const double capLimit2 = nearMesh ? kNearLimit2 : kFarBound * kFarBound;
    if (onCap.squaredDistance <= capLimit2 && onCap.squaredDistance < nearest.squaredDistance) {
      onCap.triangle += mesh_.meshTriangleCount;
      nearest = onCap;
    }
  }

  /// A voxel within sqrt(0.7) voxel of M + S, not on M, with its closest feature `nearest`: on a
  /// cap, by the winding numbers' difference; else by its closest feature's side where that
  /// decides, or left for its own winding number.
  void classifyNearVoxel(std::size_t i, openvdb::Index o, float value, const openvdb::Coord& ijk,
                         const Eigen::Vector3d& p, const NearestTriangle& nearest,
                         std::uint8_t& state, LeafSummary& summary) {
    std::uint8_t s = kActive | kNear;
    ++summary.near;
    const double distance = std::sqrt(nearest.squaredDistance);
    if (distance > kLinkDistance) s |= kLinkable;
    data_.clearances[i][o] = storedClearance(distance);
    if (distance <= kOnSurface) {
      // On a cap, off M: W and w_S both jump here, but their difference w does not.
      // On a planar hole's flat cap w is 1/2 up to rounding: ties are inside (kClosingTie).
      const bool inside = closed_.exact(p) - caps_->exact(p) >= 0.5 - kClosingTie;
      state = s | kFinal | (inside ? kInside : 0);
      if (inside != (value < 0.0f)) summary.flipped.push_back(ijk);
      return;
    }
    state = s;
    if (decideBySides_) {
      const ComponentSides& component = (*sides_)[mesh_.component[nearest.triangle]];
      const SurfaceSide side = mesh_.side(nearest.triangle, nearest.closest, p);
      if (side != SurfaceSide::unknown && component.known) {
        settle(i, o, side == SurfaceSide::back ? component.back : component.front, value);
        return;
      }
      summary.undecided.push_back(o);
    }
    // Otherwise W comes from the group the voxel joins (decideFarVoxels()).
  }

  void settleUndecided(std::size_t i) {
    LeafSummary& summary = summaries_[i];
    for (const openvdb::Index o : summary.undecided) {
      settle(i, o, windingAt(pointOf(table_.leaf(i).offsetToGlobalCoord(o))),
             table_.leaf(i).getValue(o));
      ++summary.queries;
    }
  }

  /// W and the side of every far voxel through the groups they form.
  void decideFarVoxels(BandSignReport& report) {
    FarGroups groups = joinFarGroups(table_, data_);
    reportProgress(0.55);
    const std::vector<std::int16_t> groupWinding = windingsOfGroups(groups, report);
    reportProgress(0.7);
    assignGroupWindings(groups, groupWinding);
    reportProgress(0.75);
    report.capQueries = decideFarSides();
  }

  /// Per group root: its seeds' W when they agree, kPerVoxel when they do not, or one winding
  /// number at its voxel farthest from the surface when it has no seeds. Counts the groups and
  /// conflicts.
  std::vector<std::int16_t> windingsOfGroups(FarGroups& groups, BandSignReport& report) const {
    const std::vector<std::uint32_t>& base = groups.base;
    const std::uint32_t total = base[leafCount_];
    std::vector<Seeds> seeds(total);
    // Per root, the local group holding the voxel farthest out (the first in leaf order among
    // equals, so the choice does not depend on the schedule).
    std::vector<std::uint32_t> farthest(total, kNone);
    for (std::size_t i = 0; i < leafCount_; ++i) {
      const LocalGroups& local = groups.local[i];
      for (std::uint32_t g = 0; g < local.seeds.size(); ++g) {
        const std::uint32_t root = groups.sets.find(base[i] + g);
        seeds[root].add(local.seeds[g]);
        if (farthest[root] == kNone || local.reach[g] > reachOf(groups, farthest[root])) {
          farthest[root] = base[i] + g;
        }
      }
    }
    std::vector<std::int16_t> groupWinding(total, 0);
    std::vector<std::uint32_t> seedless;
    for (std::uint32_t id = 0; id < total; ++id) {
      if (groups.sets.find(id) != id) continue;
      ++report.farComponents;
      if (seeds[id].empty()) {
        seedless.push_back(id);
      } else if (seeds[id].low != seeds[id].high) {
        groupWinding[id] = kPerVoxel;
        ++report.conflicts;
      } else {
        groupWinding[id] = seeds[id].low;
      }
    }
    tbb::parallel_for(std::size_t{0}, seedless.size(), [&](std::size_t n) {
      const std::uint32_t id = farthest[seedless[n]];
      const auto i =
          static_cast<std::size_t>(std::upper_bound(base.begin(), base.end(), id) - base.begin()) -
          1;
      const openvdb::Index o = groups.local[i].representative[id - base[i]];
      groupWinding[seedless[n]] = windingAt(pointOf(table_.leaf(i).offsetToGlobalCoord(o)));
    });
    report.windingNumberQueries += seedless.size();
    return groupWinding;
  }

  /// |value| of the representative of local group `id` (numbered as in groups.base).
  static float reachOf(const FarGroups& groups, std::uint32_t id) {
    const auto i =
        static_cast<std::size_t>(std::upper_bound(groups.base.begin(), groups.base.end(), id) -
                                 groups.base.begin()) -
        1;
    return groups.local[i].reach[id - groups.base[i]];
  }

  /// Every grouped voxel takes its group's W (its own winding number in a conflicting group).
  void assignGroupWindings(FarGroups& groups, const std::vector<std::int16_t>& groupWinding) {
    groups.sets.flatten();  // root() reads without writing, so the loop below may share the sets
    tbb::parallel_for(std::size_t{0}, leafCount_, [&](std::size_t i) {
      const LocalGroups& local = groups.local[i];
      for (openvdb::Index o = 0; o < kVoxels; ++o) {
        if (local.label[o] == kNoLabel) continue;
        const std::int16_t w = groupWinding[groups.sets.root(groups.base[i] + local.label[o])];
        if (w == kPerVoxel) {
          data_.windings[i][o] = windingAt(pointOf(table_.leaf(i).offsetToGlobalCoord(o)));
          ++summaries_[i].queries;
        } else {
          data_.windings[i][o] = w;
        }
        data_.states[i][o] |= kKnown;
      }
    });
  }

  /// Inside for every voxel not final yet: W - w_S >= 1/2 (W >= 1 without caps), compared with
  /// OpenVDB's sign. Returns the number of cap winding numbers evaluated.
  std::size_t decideFarSides() {
    std::vector<std::size_t> capQueries(leafCount_, 0);
    forLeaves(0.75, 0.95, [&](std::size_t i) {
      States& state = data_.states[i];
      const FloatLeaf& leaf = table_.leaf(i);
      for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
        std::uint8_t& s = state[voxel.pos()];
        if (s & kFinal) continue;
        const double w = data_.windings[i][voxel.pos()];
        bool inside = w >= 1.0;
        // |w_S| < 1/2 over the leaf: W - w_S >= 1/2 exactly when the integer W is at least 1.
        if (caps_ && !(capBound_[i] < 0.5)) {
          const double wS =
              caps_->decide(pointOf(voxel.getCoord()), [w](const WindingNumberField::Estimate& e) {
                return std::abs(w - e.value - 0.5) > e.errorBound;
              });
          inside = w - wS >= 0.5 - kClosingTie;
          ++capQueries[i];
        }
        s |= kFinal | (inside ? kInside : 0);
        if (inside != (*voxel < 0.0f)) summaries_[i].flipped.push_back(voxel.getCoord());
      }
    });
    return std::accumulate(capQueries.begin(), capQueries.end(), std::size_t{0});
  }

  /// Per leaf, the flipped voxels and their 26-neighbours (as one-voxel dilations along x, y
  /// and z, across the leaves' faces); counts the flips.
  std::vector<Mask> affectedVoxels(BandSignReport& report) const {
    std::vector<Mask> affected(leafCount_);
    for (std::size_t i = 0; i < leafCount_; ++i) {
      report.correctedVoxels += summaries_[i].flipped.size();
      for (const openvdb::Coord& ijk : summaries_[i].flipped) {
        const openvdb::Index o = FloatLeaf::coordToOffset(ijk);
        affected[i][o >> 6] |= std::uint64_t{1} << (o & 63);
      }
    }
    if (report.correctedVoxels == 0) return affected;
    for (int axis = 0; axis < 3; ++axis) affected = dilateAlong(affected, table_, axis);
    return affected;
  }

  /// Flipped voxels change sign; they and the near voxels around them take the exact distance to
  /// M (meshToVolume pushes surface voxels without an inside neighbour out to sqrt(3)/2 voxel,
  /// which a corrected neighbour makes wrong).
  void rewrite(const std::vector<Mask>& affected) {
    tbb::parallel_for(std::size_t{0}, leafCount_, [&](std::size_t i) {
      FloatLeaf& leaf = table_.leaf(i);
      for (openvdb::Index o = 0; o < kVoxels; ++o) {
        if (((affected[i][o >> 6] >> (o & 63)) & 1u) == 0 || !leaf.isValueOn(o)) continue;
        float magnitude = std::abs(leaf.getValue(o));
        if (magnitude <= nearValueLimit_) {
          const NearestTriangle nearest =
              closestOnMesh(closestLeaves_[i] ? closestLeaves_[i]->getValue(o) : -1,
                            pointOf(leaf.offsetToGlobalCoord(o)));
          if (nearest.squaredDistance <= kNearLimit2) {
            magnitude = static_cast<float>(std::sqrt(nearest.squaredDistance) * voxelSize_);
          }
        }
        // Far voxels left final by the bit check keep OpenVDB's sign.
        const std::uint8_t s = data_.states[i][o];
        const bool inside = (s & kFinal) ? (s & kInside) != 0 : leaf.getValue(o) < 0.0f;
        leaf.setValueOnly(o, inside ? -magnitude : magnitude);
      }
    });
  }

  openvdb::FloatGrid& grid_;
  const SignLeafTable& table_;
  const InsideOutsideMesh& mesh_;
  const WindingNumberField& closed_;
  const WindingNumberField* caps_;            ///< null without caps
  const std::vector<ComponentSides>* sides_;  ///< used only when decideBySides_
  const std::function<void(double)>& progress_;
  const bool decideBySides_;  ///< embedded, with the components' sides
  const std::size_t leafCount_;
  const double voxelSize_;
  const float nearValueLimit_;
  const std::int64_t meshTriangles_;
  std::vector<const IndexLeaf*> closestLeaves_;  ///< per leaf, the same leaf of `closest`
  VoxelData data_;                               ///< states, W and clearances of every voxel
  std::vector<LeafSummary> summaries_;
  std::vector<char> capsNear_;    ///< with caps, per leaf: a cap may be near one of its voxels
  std::vector<double> capBound_;  ///< with caps, per leaf: a bound on |w_S| at its voxels
};

}  // namespace

std::vector<ComponentSides> componentSides(const InsideOutsideMesh& mesh,
                                           const WindingNumberField& closed) {
  std::vector<ComponentSides> sides(mesh.componentCount);
  std::vector<std::uint32_t> face(mesh.componentCount, kNone);
  std::vector<double> largest(mesh.componentCount, 0.0);
  std::vector<double> volume(mesh.componentCount, 0.0);
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const TriangleIndices& tri = mesh.triangles[t];
    const Eigen::Vector3d& a = mesh.points[tri[0]];
    const Eigen::Vector3d& b = mesh.points[tri[1]];
    const Eigen::Vector3d& c = mesh.points[tri[2]];
    volume[mesh.component[t]] += a.dot(b.cross(c));
    if (mesh.degenerate[t]) continue;
    const double area = (b - a).cross(c - a).norm();
    if (area > largest[mesh.component[t]]) {
      largest[mesh.component[t]] = area;
      face[mesh.component[t]] = t;
    }
  }
  tbb::parallel_for(std::size_t{0}, std::size_t{mesh.componentCount}, [&](std::size_t c) {
    if (face[c] == kNone) return;
    const TriangleIndices& tri = mesh.triangles[face[c]];
    const Eigen::Vector3d centroid =
        (mesh.points[tri[0]] + mesh.points[tri[1]] + mesh.points[tri[2]]) / 3.0;
    const double value = closed.decide(
        centroid,
        [](const WindingNumberField::Estimate& e) {
          const double shifted = e.value - 0.5;
          return std::abs(shifted - std::round(shifted)) + e.errorBound < 0.5;
        },
        face[c]);
    const long front = std::clamp<long>(std::lround(value - 0.5), -32000, 32000);
    ComponentSides& side = sides[c];
    side.front = static_cast<std::int16_t>(front);
    side.back = static_cast<std::int16_t>(front + 1);
    side.known = true;
    // The other components' winding number here: W behind the face less this component's own
    // (1 behind an outward-wound closed component, 0 behind an inward-wound one).
    side.enclosed = (side.back - (volume[c] > 0.0 ? 1 : 0)) != 0;
  });
  return sides;
}

BandSignReport correctBandSigns(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closest,
                                const BandSignInputs& inputs) {
  const SignLeafTable table(grid.tree());
  if (table.size() == 0) return BandSignReport{};
  BandSignCorrection correction(grid, closest, inputs, table);
  return correction.run();
}

}  // namespace d2vdb::detail
