// Regions of one side of the band, labelled per leaf and joined across the leaves' faces; the
// enclosed ones that only open or non-manifold parts of the mesh bound change sides.
#include "d2vdb/field/detail/SignPockets.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <numeric>

#include "d2vdb/core/detail/DisjointSets.h"

namespace d2vdb::detail {
namespace {

using openvdb::Coord;
using FloatLeaf = openvdb::FloatTree::LeafNodeType;
constexpr int kDim = FloatLeaf::DIM;
constexpr openvdb::Index kVoxels = FloatLeaf::SIZE;
constexpr std::uint16_t kNoLabel = std::numeric_limits<std::uint16_t>::max();

openvdb::Index offsetOf(int x, int y, int z) {
  return static_cast<openvdb::Index>((x << (2 * FloatLeaf::LOG2DIM)) + (y << FloatLeaf::LOG2DIM) +
                                     z);
}

/// The regions of one leaf: 6-connected active voxels of one side, linked inside the leaf only.
struct LocalRegions {
  std::array<std::uint16_t, kVoxels> label;  ///< region of each active voxel, or kNoLabel
  std::vector<std::uint32_t> size;
  std::vector<char> inside, touchesInactive, nearOpen;
};

/// What the joined regions have in common: the sums and unions of their local parts.
struct RegionSummary {
  std::uint64_t size = 0;
  bool inside = false, touchesInactive = false, nearOpen = false;
};

class PocketFinder {
 public:
  PocketFinder(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closest,
               const InsideOutsideMesh& mesh, const std::vector<bool>& closedComponent)
      : grid_(grid), closest_(closest), mesh_(mesh), closedComponent_(closedComponent) {
    leaves_.reserve(grid.tree().leafCount());
    grid.tree().getNodes(leaves_);
    origins_.resize(leaves_.size());
    for (std::size_t i = 0; i < leaves_.size(); ++i) origins_[i] = {leaves_[i]->origin(), i};
    std::sort(origins_.begin(), origins_.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
  }

  SignPocketReport run() {
    SignPocketReport report;
    local_.resize(leaves_.size());
    tbb::parallel_for(std::size_t{0}, leaves_.size(), [this](std::size_t i) { labelLeaf(i); });
    std::vector<std::uint32_t> base(leaves_.size() + 1, 0);
    for (std::size_t i = 0; i < leaves_.size(); ++i) {
      base[i + 1] = base[i] + static_cast<std::uint32_t>(local_[i].size.size());
    }
    DisjointSets<std::uint32_t> sets(base.back());
    joinAcrossFaces(base, sets);
    std::vector<RegionSummary> summary(base.back());
    for (std::size_t i = 0; i < leaves_.size(); ++i) {
      const LocalRegions& local = local_[i];
      for (std::uint32_t g = 0; g < local.size.size(); ++g) {
        RegionSummary& s = summary[sets.find(base[i] + g)];
        s.size += local.size[g];
        s.inside = local.inside[g] != 0;
        s.touchesInactive = s.touchesInactive || local.touchesInactive[g] != 0;
        s.nearOpen = s.nearOpen || local.nearOpen[g] != 0;
      }
    }
    std::vector<char> pocket(base.back(), 0);
    for (std::uint32_t id = 0; id < base.back(); ++id) {
      if (!sets.isRoot(id)) continue;
      const RegionSummary& s = summary[id];
      if (s.touchesInactive || !s.nearOpen) continue;
      if (s.inside && s.size > kMaxSpeckVoxels) continue;
      pocket[id] = 1;
      ++report.pockets;
      report.voxels += s.size;
    }
    if (report.pockets == 0) return report;
    sets.flatten();
    tbb::parallel_for(std::size_t{0}, leaves_.size(), [&](std::size_t i) {
      FloatLeaf& leaf = *leaves_[i];
      for (auto voxel = leaf.beginValueOn(); voxel; ++voxel) {
        const std::uint16_t label = local_[i].label[voxel.pos()];
        if (!pocket[sets.root(base[i] + label)]) continue;
        const float v = *voxel;
        const float magnitude = std::max(std::abs(v), std::numeric_limits<float>::min());
        voxel.setValue(v < 0.0f ? magnitude : -magnitude);
      }
    });
    return report;
  }

 private:
  /// Index of the leaf with this origin, or leaves_.size().
  std::size_t findLeaf(const Coord& origin) const {
    const auto found =
        std::lower_bound(origins_.begin(), origins_.end(), origin,
                         [](const auto& entry, const Coord& key) { return entry.first < key; });
    return found != origins_.end() && found->first == origin ? found->second : leaves_.size();
  }

  /// Whether the closest triangle recorded at `ijk` lies on a component that is not a closed
  /// 2-manifold.
  bool nearOpenPart(const openvdb::tree::ValueAccessor<const openvdb::Int32Tree>& indices,
                    const Coord& ijk) const {
    const std::int64_t t = indices.getValue(ijk);
    if (t < 0 || t >= static_cast<std::int64_t>(mesh_.meshTriangleCount)) return false;
    return !closedComponent_[mesh_.component[static_cast<std::size_t>(t)]];
  }

  void labelLeaf(std::size_t i) {
    const FloatLeaf& leaf = *leaves_[i];
    LocalRegions& local = local_[i];
    local.label.fill(kNoLabel);
    std::array<std::uint16_t, kVoxels> parent;
    std::iota(parent.begin(), parent.end(), std::uint16_t{0});
    const auto find = [&parent](std::uint16_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    const auto sameSide = [&leaf](openvdb::Index a, openvdb::Index b) {
      return leaf.isValueOn(b) && (leaf.getValue(a) < 0.0f) == (leaf.getValue(b) < 0.0f);
    };
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      const openvdb::Index o = voxel.pos();
      const Coord c = FloatLeaf::offsetToLocalCoord(o);
      const std::array<bool, 3> inLeaf{c.x() + 1 < kDim, c.y() + 1 < kDim, c.z() + 1 < kDim};
      const std::array<openvdb::Index, 3> next{offsetOf(c.x() + 1, c.y(), c.z()),
                                               offsetOf(c.x(), c.y() + 1, c.z()),
                                               offsetOf(c.x(), c.y(), c.z() + 1)};
      for (int axis = 0; axis < 3; ++axis) {
        if (!inLeaf[axis] || !sameSide(o, next[axis])) continue;
        const std::uint16_t a = find(static_cast<std::uint16_t>(o));
        const std::uint16_t b = find(static_cast<std::uint16_t>(next[axis]));
        parent[std::max(a, b)] = std::min(a, b);
      }
    }
    const openvdb::tree::ValueAccessor<const openvdb::FloatTree> values(grid_.constTree());
    const openvdb::tree::ValueAccessor<const openvdb::Int32Tree> indices(closest_.tree());
    std::array<std::uint16_t, kVoxels> labelOfRoot;
    labelOfRoot.fill(kNoLabel);
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      const openvdb::Index o = voxel.pos();
      const std::uint16_t root = find(static_cast<std::uint16_t>(o));
      if (labelOfRoot[root] == kNoLabel) {
        labelOfRoot[root] = static_cast<std::uint16_t>(local.size.size());
        local.size.push_back(0);
        local.inside.push_back(*voxel < 0.0f ? 1 : 0);
        local.touchesInactive.push_back(0);
        local.nearOpen.push_back(0);
      }
      const std::uint16_t g = labelOfRoot[root];
      local.label[o] = g;
      ++local.size[g];
      const Coord ijk = voxel.getCoord();
      for (int axis = 0; axis < 3 && !local.touchesInactive[g]; ++axis) {
        for (const int step : {-1, 1}) {
          Coord n = ijk;
          n[axis] += step;
          if (!values.isValueOn(n)) local.touchesInactive[g] = 1;
        }
      }
      if (!local.nearOpen[g] && nearOpenPart(indices, ijk)) local.nearOpen[g] = 1;
    }
  }

  /// Unites the regions of face-adjacent voxels of one side in neighbouring leaves (+x, +y, +z).
  void joinAcrossFaces(const std::vector<std::uint32_t>& base,
                       DisjointSets<std::uint32_t>& sets) const {
    for (std::size_t i = 0; i < leaves_.size(); ++i) {
      const FloatLeaf& leaf = *leaves_[i];
      for (int axis = 0; axis < 3; ++axis) {
        Coord origin = leaf.origin();
        origin[axis] += kDim;
        const std::size_t j = findLeaf(origin);
        if (j == leaves_.size()) continue;
        const FloatLeaf& other = *leaves_[j];
        for (int u = 0; u < kDim; ++u) {
          for (int v = 0; v < kDim; ++v) {
            std::array<int, 3> a{}, b{};
            a[axis] = kDim - 1;
            b[axis] = 0;
            a[(axis + 1) % 3] = b[(axis + 1) % 3] = u;
            a[(axis + 2) % 3] = b[(axis + 2) % 3] = v;
            const openvdb::Index oa = offsetOf(a[0], a[1], a[2]);
            const openvdb::Index ob = offsetOf(b[0], b[1], b[2]);
            if (!leaf.isValueOn(oa) || !other.isValueOn(ob)) continue;
            if ((leaf.getValue(oa) < 0.0f) != (other.getValue(ob) < 0.0f)) continue;
            sets.unite(base[i] + local_[i].label[oa], base[j] + local_[j].label[ob]);
          }
        }
      }
    }
  }

  openvdb::FloatGrid& grid_;
  const openvdb::Int32Grid& closest_;
  const InsideOutsideMesh& mesh_;
  const std::vector<bool>& closedComponent_;
  std::vector<FloatLeaf*> leaves_;
  std::vector<std::pair<Coord, std::size_t>> origins_;
  std::vector<LocalRegions> local_;
};

}  // namespace

std::vector<bool> closedComponents(const InsideOutsideMesh& mesh) {
  std::vector<bool> closed(mesh.componentCount, true);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::uint32_t c = mesh.component[t];
    if (t >= mesh.meshTriangleCount) closed[c] = false;
    for (int k = 0; k < 3; ++k) {
      if (mesh.mate[3 * t + static_cast<std::size_t>(k)] == InsideOutsideMesh::kNoMate) {
        closed[c] = false;
      }
    }
  }
  return closed;
}

SignPocketReport fillSignPockets(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closest,
                                 const InsideOutsideMesh& mesh,
                                 const std::vector<bool>& intersecting) {
  // A component that meets another one, or itself, bounds no cavity of its own.
  std::vector<bool> closed = closedComponents(mesh);
  for (std::size_t t = 0; t < intersecting.size() && t < mesh.component.size(); ++t) {
    if (intersecting[t]) closed[mesh.component[t]] = false;
  }
  if (std::all_of(closed.begin(), closed.end(), [](bool c) { return c; })) return {};
  PocketFinder finder(grid, closest, mesh, closed);
  return finder.run();
}

}  // namespace d2vdb::detail
