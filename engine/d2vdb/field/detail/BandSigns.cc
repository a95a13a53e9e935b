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
#include <vector>

#include "d2vdb/field/detail/TriangleClosestPoint.h"

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
/// Voxel centres this close to the mesh (voxels) keep OpenVDB's sign: either side is right.
constexpr double kOnSurface = 1e-6;

// Voxel state bits.
constexpr std::uint8_t kActive = 1;
constexpr std::uint8_t kNear = 2;
constexpr std::uint8_t kDecided = 4;
constexpr std::uint8_t kInside = 8;
constexpr std::uint8_t kLinkable = 16;
constexpr std::uint8_t kKeep = 32;

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint16_t kNoLabel = std::numeric_limits<std::uint16_t>::max();

using States = std::array<std::uint8_t, kVoxels>;

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
class LeafTable {
 public:
  explicit LeafTable(openvdb::FloatTree& tree) {
    leaves_.reserve(tree.leafCount());
    tree.getNodes(leaves_);
    sorted_.resize(leaves_.size());
    for (std::uint32_t i = 0; i < leaves_.size(); ++i) sorted_[i] = {leaves_[i]->origin(), i};
    std::sort(sorted_.begin(), sorted_.end(),
              [](const Entry& a, const Entry& b) { return a.origin < b.origin; });
    neighbours_.resize(leaves_.size());
    tbb::parallel_for(std::size_t{0}, leaves_.size(), [this](std::size_t i) {
      const openvdb::Coord origin = leaves_[i]->origin();
      for (int axis = 0; axis < 3; ++axis) {
        for (int direction = 0; direction < 2; ++direction) {
          openvdb::Coord other = origin;
          other[axis] += direction == 0 ? -kDim : kDim;
          neighbours_[i][2 * axis + direction] = find(other);
        }
      }
    });
  }

  std::size_t size() const { return leaves_.size(); }
  FloatLeaf& leaf(std::size_t i) const { return *leaves_[i]; }
  /// Neighbour across face 2 * axis + (0 for -, 1 for +), or kNone.
  std::uint32_t neighbour(std::size_t i, int face) const { return neighbours_[i][face]; }

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
  std::vector<std::array<std::uint32_t, 6>> neighbours_;
};

/// The state of the voxel at local coordinates (x, y, z) of leaf i, looking into the face
/// neighbour when one coordinate is just outside the leaf (0 = inactive or no leaf).
std::uint8_t stateAt(const LeafTable& table, const std::vector<States>& states, std::size_t i,
                     int x, int y, int z) {
  int face = -1;
  if (x < 0)
    face = 0, x += kDim;
  else if (x >= kDim)
    face = 1, x -= kDim;
  else if (y < 0)
    face = 2, y += kDim;
  else if (y >= kDim)
    face = 3, y -= kDim;
  else if (z < 0)
    face = 4, z += kDim;
  else if (z >= kDim)
    face = 5, z -= kDim;
  std::size_t leaf = i;
  if (face >= 0) {
    const std::uint32_t other = table.neighbour(i, face);
    if (other == kNone) return 0;
    leaf = other;
  }
  return states[leaf][offsetOf(x, y, z)];
}

/// Union-find whose roots are the smallest members (so that representatives do not depend on
/// the order of the unions).
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t size) : parent_(size) {
    std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
  }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a < b)
      parent_[b] = a;
    else if (b < a)
      parent_[a] = b;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

/// Far voxels of one leaf grouped by 6-adjacency inside the leaf.
struct LocalGroups {
  std::array<std::uint16_t, kVoxels> label;   ///< group of each far voxel, or kNoLabel
  std::vector<std::uint16_t> representative;  ///< first voxel (offset) of each group
  std::vector<std::uint8_t> seeds;  ///< per group: 1 = an inside near neighbour, 2 = outside
};

LocalGroups groupFarVoxels(const LeafTable& table, const std::vector<States>& states,
                           std::size_t i) {
  LocalGroups groups;
  groups.label.fill(kNoLabel);
  const States& state = states[i];
  const auto isFar = [](std::uint8_t s) { return (s & kActive) && !(s & kNear); };
  std::array<std::uint16_t, kVoxels> parent;
  const auto find = [&parent](std::uint16_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  for (openvdb::Index o = 0; o < kVoxels; ++o) parent[o] = static_cast<std::uint16_t>(o);
  for (int x = 0; x < kDim; ++x) {
    for (int y = 0; y < kDim; ++y) {
      for (int z = 0; z < kDim; ++z) {
        const openvdb::Index o = offsetOf(x, y, z);
        if (!isFar(state[o])) continue;
        const auto link = [&](openvdb::Index other) {
          if (!isFar(state[other])) return;
          const std::uint16_t a = find(static_cast<std::uint16_t>(o));
          const std::uint16_t b = find(static_cast<std::uint16_t>(other));
          if (a < b)
            parent[b] = a;
          else if (b < a)
            parent[a] = b;
        };
        if (x > 0) link(offsetOf(x - 1, y, z));
        if (y > 0) link(offsetOf(x, y - 1, z));
        if (z > 0) link(offsetOf(x, y, z - 1));
      }
    }
  }
  for (openvdb::Index o = 0; o < kVoxels; ++o) {
    if (!isFar(state[o])) continue;
    const std::uint16_t root = find(static_cast<std::uint16_t>(o));
    if (groups.label[root] == kNoLabel) {
      groups.label[root] = static_cast<std::uint16_t>(groups.representative.size());
      groups.representative.push_back(static_cast<std::uint16_t>(o));
      groups.seeds.push_back(0);
    }
    groups.label[o] = groups.label[root];
  }
  // Seeds: near 6-neighbours far enough from the mesh that no surface passes between.
  static constexpr int kSteps[6][3] = {{-1, 0, 0}, {1, 0, 0},  {0, -1, 0},
                                       {0, 1, 0},  {0, 0, -1}, {0, 0, 1}};
  for (int x = 0; x < kDim; ++x) {
    for (int y = 0; y < kDim; ++y) {
      for (int z = 0; z < kDim; ++z) {
        const openvdb::Index o = offsetOf(x, y, z);
        if (groups.label[o] == kNoLabel) continue;
        for (const auto& step : kSteps) {
          const std::uint8_t s = stateAt(table, states, i, x + step[0], y + step[1], z + step[2]);
          constexpr std::uint8_t kSeed = kActive | kNear | kDecided | kLinkable;
          if ((s & kSeed) == kSeed) groups.seeds[groups.label[o]] |= (s & kInside) ? 1 : 2;
        }
      }
    }
  }
  return groups;
}

}  // namespace

BandSignReport correctBandSigns(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closest,
                                const InsideOutsideMesh& mesh, const WindingNumberField& winding,
                                BandSignMode mode) {
  BandSignReport report;
  const LeafTable table(grid.tree());
  const std::size_t leafCount = table.size();
  if (leafCount == 0) return report;
  const double voxelSize = grid.voxelSize()[0];
  const float background = grid.background();
  const bool integerWinding = mode != BandSignMode::windingNumberEveryVoxel;
  const auto triangleCount = static_cast<std::int64_t>(mesh.triangles.size());

  std::vector<const IndexLeaf*> closestLeaves(leafCount);
  for (std::size_t i = 0; i < leafCount; ++i) {
    closestLeaves[i] = closest.tree().probeConstLeaf(table.leaf(i).origin());
  }

  // The winding number on the front and back of each edge-connected component: at the centroid
  // of its largest face, without that face, plus or minus 1/2.
  std::vector<std::array<long, 2>> sideWinding;
  std::vector<bool> sideKnown;
  if (mode == BandSignMode::closestFeature) {
    std::vector<std::uint32_t> face(mesh.componentCount, kNone);
    std::vector<double> largest(mesh.componentCount, 0.0);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.degenerate[t]) continue;
      const TriangleIndices& tri = mesh.triangles[t];
      const double area = (mesh.points[tri[1]] - mesh.points[tri[0]])
                              .cross(mesh.points[tri[2]] - mesh.points[tri[0]])
                              .norm();
      if (area > largest[mesh.component[t]]) {
        largest[mesh.component[t]] = area;
        face[mesh.component[t]] = t;
      }
    }
    sideWinding.assign(mesh.componentCount, {0, 0});
    sideKnown.assign(mesh.componentCount, false);
    std::vector<std::uint8_t> known(mesh.componentCount, 0);
    tbb::parallel_for(std::size_t{0}, std::size_t{mesh.componentCount}, [&](std::size_t c) {
      if (face[c] == kNone) return;
      const TriangleIndices& tri = mesh.triangles[face[c]];
      const Eigen::Vector3d centroid =
          (mesh.points[tri[0]] + mesh.points[tri[1]] + mesh.points[tri[2]]) / 3.0;
      const double value = winding.decide(
          centroid,
          [](const WindingNumberField::Estimate& e) {
            const double shifted = e.value - 0.5;
            return std::abs(shifted - std::round(shifted)) + e.errorBound < 0.5;
          },
          face[c]);
      const long front = std::lround(value - 0.5);
      sideWinding[c] = {front, front + 1};
      known[c] = 1;
    });
    for (std::size_t c = 0; c < known.size(); ++c) {
      sideKnown[c] = known[c] != 0;
      if (sideKnown[c]) ++report.windingNumberQueries;
    }
  }

  // Near voxels: exact closest point, then the closest-feature side where it is decisive.
  std::vector<States> states(leafCount);
  std::vector<std::size_t> nearCounts(leafCount, 0);
  tbb::parallel_for(std::size_t{0}, leafCount, [&](std::size_t i) {
    States& state = states[i];
    state.fill(0);
    const FloatLeaf& leaf = table.leaf(i);
    const IndexLeaf* indices = closestLeaves[i];
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      const openvdb::Index o = voxel.pos();
      std::uint8_t s = kActive;
      const std::int64_t t = indices ? indices->getValue(o) : -1;
      if (t >= 0 && t < triangleCount) {
        const openvdb::Coord ijk = voxel.getCoord();
        const Eigen::Vector3d p(ijk.x(), ijk.y(), ijk.z());
        const TriangleIndices& tri = mesh.triangles[static_cast<std::size_t>(t)];
        const TriangleClosestPoint closestPoint = closestPointOnTriangle(
            p, mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]);
        const double distance2 = (p - closestPoint.point).squaredNorm();
        if (distance2 <= kNearLimit2) {
          s |= kNear;
          ++nearCounts[i];
          const double distance = std::sqrt(distance2);
          if (distance > kLinkDistance) s |= kLinkable;
          if (distance <= kOnSurface) {
            s |= kDecided | kKeep | (*voxel < 0.0f ? kInside : 0);
          } else if (mode == BandSignMode::closestFeature) {
            const std::uint32_t component = mesh.component[static_cast<std::size_t>(t)];
            const SurfaceSide side = mesh.side(static_cast<std::uint32_t>(t), closestPoint, p);
            if (side != SurfaceSide::unknown && sideKnown[component]) {
              const long w = sideWinding[component][side == SurfaceSide::back ? 1 : 0];
              s |= kDecided | (w >= 1 ? kInside : 0);
            }
          }
        }
      }
      state[o] = s;
    }
  });
  report.nearVoxels = std::accumulate(nearCounts.begin(), nearCounts.end(), std::size_t{0});

  // Winding numbers one voxel at a time where nothing cheaper decides.
  std::vector<std::size_t> queries(leafCount, 0);
  const auto evaluate = [&](const openvdb::Coord& ijk) {
    const Eigen::Vector3d p(ijk.x(), ijk.y(), ijk.z());
    return integerWinding ? winding.integerValue(p) >= 1 : winding.atLeastHalf(p);
  };
  tbb::parallel_for(std::size_t{0}, leafCount, [&](std::size_t i) {
    States& state = states[i];
    const FloatLeaf& leaf = table.leaf(i);
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      std::uint8_t& s = state[voxel.pos()];
      if (s & kDecided) continue;
      if (integerWinding && !(s & kNear)) continue;  // far voxels: by groups below
      s |= kDecided | (evaluate(voxel.getCoord()) ? kInside : 0);
      ++queries[i];
    }
  });

  // Far voxels of a watertight mesh: groups, their seeds, one winding number for a seedless one.
  if (integerWinding) {
    std::vector<LocalGroups> groups(leafCount);
    tbb::parallel_for(std::size_t{0}, leafCount,
                      [&](std::size_t i) { groups[i] = groupFarVoxels(table, states, i); });
    std::vector<std::uint32_t> base(leafCount + 1, 0);
    for (std::size_t i = 0; i < leafCount; ++i) {
      base[i + 1] = base[i] + static_cast<std::uint32_t>(groups[i].representative.size());
    }
    DisjointSets sets(base[leafCount]);
    for (std::size_t i = 0; i < leafCount; ++i) {
      for (int axis = 0; axis < 3; ++axis) {
        const std::uint32_t j = table.neighbour(i, 2 * axis + 1);
        if (j == kNone) continue;
        for (int u = 0; u < kDim; ++u) {
          for (int v = 0; v < kDim; ++v) {
            const openvdb::Index high = faceOffset(axis, kDim - 1, u, v);
            const openvdb::Index low = faceOffset(axis, 0, u, v);
            const std::uint16_t a = groups[i].label[high];
            const std::uint16_t b = groups[j].label[low];
            if (a != kNoLabel && b != kNoLabel) sets.unite(base[i] + a, base[j] + b);
          }
        }
      }
    }
    const std::uint32_t total = base[leafCount];
    std::vector<std::uint8_t> seeds(total, 0);
    for (std::size_t i = 0; i < leafCount; ++i) {
      for (std::uint32_t g = 0; g < groups[i].seeds.size(); ++g) {
        seeds[sets.find(base[i] + g)] |= groups[i].seeds[g];
      }
    }
    // Decide each set at its root (its smallest member).
    std::vector<std::uint32_t> seedless;
    std::vector<std::uint8_t> decision(total, 0);  // 1 inside, 2 outside, 3 per voxel
    for (std::uint32_t id = 0; id < total; ++id) {
      if (sets.find(id) != id) continue;
      ++report.farComponents;
      if (seeds[id] == 0) {
        seedless.push_back(id);
      } else {
        decision[id] = seeds[id];
        if (seeds[id] == 3) ++report.conflicts;
      }
    }
    tbb::parallel_for(std::size_t{0}, seedless.size(), [&](std::size_t n) {
      const std::uint32_t id = seedless[n];
      const std::size_t i =
          static_cast<std::size_t>(std::upper_bound(base.begin(), base.end(), id) - base.begin()) -
          1;
      const openvdb::Index o = groups[i].representative[id - base[i]];
      const openvdb::Coord ijk = table.leaf(i).offsetToGlobalCoord(o);
      decision[id] = evaluate(ijk) ? 1 : 2;
    });
    report.windingNumberQueries += seedless.size();
    tbb::parallel_for(std::size_t{0}, leafCount, [&](std::size_t i) {
      States& state = states[i];
      for (openvdb::Index o = 0; o < kVoxels; ++o) {
        if (groups[i].label[o] == kNoLabel) continue;
        const std::uint8_t d = decision[sets.find(base[i] + groups[i].label[o])];
        if (d == 3) {
          state[o] |= kDecided | (evaluate(table.leaf(i).offsetToGlobalCoord(o)) ? kInside : 0);
          ++queries[i];
        } else {
          state[o] |= kDecided | (d == 1 ? kInside : 0);
        }
      }
    });
  }
  report.windingNumberQueries += std::accumulate(queries.begin(), queries.end(), std::size_t{0});

  // Compare with OpenVDB's signs.
  std::vector<std::vector<openvdb::Coord>> flipped(leafCount);
  tbb::parallel_for(std::size_t{0}, leafCount, [&](std::size_t i) {
    const States& state = states[i];
    const FloatLeaf& leaf = table.leaf(i);
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      const std::uint8_t s = state[voxel.pos()];
      if (!(s & kDecided) || (s & kKeep)) continue;
      if (((s & kInside) != 0) != (*voxel < 0.0f)) flipped[i].push_back(voxel.getCoord());
    }
  });
  std::vector<openvdb::Coord> affected;
  for (const std::vector<openvdb::Coord>& list : flipped) {
    report.correctedVoxels += list.size();
    for (const openvdb::Coord& ijk : list) {
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) affected.push_back(ijk.offsetBy(dx, dy, dz));
    }
  }
  if (report.correctedVoxels == 0) return report;
  std::sort(affected.begin(), affected.end());
  affected.erase(std::unique(affected.begin(), affected.end()), affected.end());

  // Flipped voxels and their neighbours: the distance to their closest triangle, with their sign.
  const float largest = background * (1.0f - 1e-6f);
  tbb::parallel_for(std::size_t{0}, affected.size(), [&](std::size_t n) {
    const openvdb::Coord& ijk = affected[n];
    const std::uint32_t i = table.find(ijk & ~(kDim - 1));
    if (i == kNone) return;
    FloatLeaf& leaf = table.leaf(i);
    const openvdb::Index o = FloatLeaf::coordToOffset(ijk);
    if (!leaf.isValueOn(o)) return;
    const std::uint8_t s = states[i][o];
    float magnitude = std::abs(leaf.getValue(o));
    const std::int64_t t = closestLeaves[i] ? closestLeaves[i]->getValue(o) : -1;
    if (t >= 0 && t < triangleCount) {
      const Eigen::Vector3d p(ijk.x(), ijk.y(), ijk.z());
      const TriangleIndices& tri = mesh.triangles[static_cast<std::size_t>(t)];
      const TriangleClosestPoint closestPoint =
          closestPointOnTriangle(p, mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]);
      magnitude = static_cast<float>((p - closestPoint.point).norm() * voxelSize);
    }
    magnitude = std::min(magnitude, largest);
    leaf.setValueOnly(o, (s & kInside) ? -magnitude : magnitude);
  });
  openvdb::tools::signedFloodFillWithValues(grid.tree(), background, -background);
  return report;
}

}  // namespace d2vdb::detail
