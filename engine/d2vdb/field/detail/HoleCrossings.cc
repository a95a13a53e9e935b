// The search along the surfaces that close a mesh's holes, beyond the band: exact sides of the
// voxels around it, the activated voxels, then the inactive values and tiles around them.
#include "d2vdb/field/detail/HoleCrossings.h"

#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "d2vdb/field/detail/RayWinding.h"

namespace d2vdb::detail {
namespace {

using openvdb::Coord;
using FloatLeaf = openvdb::FloatTree::LeafNodeType;
using ConstAccessor = openvdb::tree::ValueAccessor<const openvdb::FloatTree>;

/// A hash of voxel coordinates (the three 32-bit values mixed by odd multipliers).
struct CoordHash {
  std::size_t operator()(const Coord& c) const {
    std::uint64_t h = std::uint64_t(std::uint32_t(c.x())) * 0x9E3779B97F4A7C15ull;
    h ^= std::uint64_t(std::uint32_t(c.y())) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= std::uint64_t(std::uint32_t(c.z())) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

constexpr std::array<std::array<int, 3>, 6> kFaceSteps{
    {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}};

bool coordLess(const Coord& a, const Coord& b) {
  return a < b;
}

void sortUnique(std::vector<Coord>& coords) {
  std::sort(coords.begin(), coords.end(), coordLess);
  coords.erase(std::unique(coords.begin(), coords.end()), coords.end());
}

Eigen::Vector3d pointOf(const Coord& ijk) {
  return Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z());
}

/// The exact sides of voxels off the band, evaluated once each (in parallel, per batch).
class SideCache {
 public:
  SideCache(const InsideOutsideMesh& mesh, const WindingNumberField& closed,
            const WindingNumberField& caps)
      : mesh_(mesh), closed_(closed), caps_(caps) {}

  /// Evaluates the voxels of `coords` (sorted, distinct) not evaluated yet.
  void evaluate(const std::vector<Coord>& coords) {
    std::vector<Coord> missing;
    for (const Coord& c : coords) {
      if (inside_.find(c) == inside_.end()) missing.push_back(c);
    }
    std::vector<char> sides(missing.size(), 0);
    tbb::parallel_for(std::size_t{0}, missing.size(), [&](std::size_t k) {
      sides[k] = insideOfMesh(mesh_, closed_, caps_, pointOf(missing[k])) ? 1 : 0;
    });
    for (std::size_t k = 0; k < missing.size(); ++k) inside_.emplace(missing[k], sides[k] != 0);
    queries_ += missing.size();
  }

  /// The side of an evaluated voxel. Safe from many threads between evaluate() calls.
  bool inside(const Coord& c) const { return inside_.at(c); }
  std::size_t queries() const { return queries_; }

 private:
  const InsideOutsideMesh& mesh_;
  const WindingNumberField& closed_;
  const WindingNumberField& caps_;
  std::unordered_map<Coord, bool, CoordHash> inside_;
  std::size_t queries_ = 0;
};

/// The first voxels to test: inactive 6-neighbours of the active voxels of every leaf where
/// the caps' winding number may reach 1/2 (a bound over the leaf grown by a voxel).
std::vector<Coord> seedVoxels(const openvdb::FloatTree& tree, const WindingNumberField& caps) {
  std::vector<const FloatLeaf*> leaves;
  leaves.reserve(tree.leafCount());
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) leaves.push_back(&*leaf);
  std::vector<std::vector<Coord>> perLeaf(leaves.size());
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t i) {
    const FloatLeaf& leaf = *leaves[i];
    const Eigen::Vector3d low = pointOf(leaf.origin()) - Eigen::Vector3d::Ones();
    const Eigen::Vector3d high = low + Eigen::Vector3d::Constant(FloatLeaf::DIM + 1);
    if (caps.boundOverBox(low, high, 0.5) < 0.5) return;
    ConstAccessor accessor(tree);
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      for (const auto& step : kFaceSteps) {
        const Coord n = voxel.getCoord().offsetBy(step[0], step[1], step[2]);
        if (!accessor.isValueOn(n)) perLeaf[i].push_back(n);
      }
    }
  });
  std::vector<Coord> seeds;
  for (const std::vector<Coord>& coords : perLeaf)
    seeds.insert(seeds.end(), coords.begin(), coords.end());
  sortUnique(seeds);
  return seeds;
}

/// The voxels off the band next to a side change, found by the search from `frontier`: in
/// rounds, every voxel of the frontier is tested (its side against its 6-neighbours'), and the
/// untested inactive 26-neighbours of the voxels that pass form the next frontier. The result is
/// sorted and does not depend on the schedule (each test is a fixed function of exact sides).
std::vector<Coord> crossingVoxels(const openvdb::FloatTree& tree, std::vector<Coord> frontier,
                                  SideCache& cache) {
  std::vector<Coord> members;
  std::unordered_set<Coord, CoordHash> tested;
  const ConstAccessor probe(tree);
  while (!frontier.empty()) {
    std::vector<Coord> needed = frontier;
    for (const Coord& c : frontier) {
      for (const auto& step : kFaceSteps) {
        const Coord n = c.offsetBy(step[0], step[1], step[2]);
        if (!probe.isValueOn(n)) needed.push_back(n);
      }
    }
    sortUnique(needed);
    cache.evaluate(needed);
    std::vector<char> member(frontier.size(), 0);
    tbb::parallel_for(std::size_t{0}, frontier.size(), [&](std::size_t k) {
      ConstAccessor accessor(tree);
      const bool inside = cache.inside(frontier[k]);
      for (const auto& step : kFaceSteps) {
        const Coord n = frontier[k].offsetBy(step[0], step[1], step[2]);
        const bool other = accessor.isValueOn(n) ? accessor.getValue(n) < 0.0f : cache.inside(n);
        if (other != inside) member[k] = 1;
      }
    });
    for (const Coord& c : frontier) tested.insert(c);
    std::vector<Coord> next;
    for (std::size_t k = 0; k < frontier.size(); ++k) {
      if (!member[k]) continue;
      members.push_back(frontier[k]);
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            const Coord n = frontier[k].offsetBy(dx, dy, dz);
            if (!probe.isValueOn(n) && tested.find(n) == tested.end()) next.push_back(n);
          }
        }
      }
    }
    sortUnique(next);
    frontier.swap(next);
  }
  sortUnique(members);
  return members;
}

/// Every inactive voxel of the leaves holding `members` takes +-background by its exact side.
void setInactiveSides(openvdb::FloatTree& tree, const std::vector<Coord>& members,
                      SideCache& cache) {
  std::vector<Coord> origins;
  origins.reserve(members.size());
  for (const Coord& c : members) origins.push_back(Coord(c.x() & ~7, c.y() & ~7, c.z() & ~7));
  sortUnique(origins);
  std::vector<FloatLeaf*> leaves(origins.size(), nullptr);
  std::vector<Coord> inactive;
  for (std::size_t i = 0; i < origins.size(); ++i) {
    leaves[i] = tree.probeLeaf(origins[i]);
    for (auto voxel = leaves[i]->cbeginValueOff(); voxel; ++voxel) {
      inactive.push_back(voxel.getCoord());
    }
  }
  sortUnique(inactive);
  cache.evaluate(inactive);
  const float background = tree.background();
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t i) {
    FloatLeaf& leaf = *leaves[i];
    for (openvdb::Index o = 0; o < FloatLeaf::SIZE; ++o) {
      if (leaf.isValueOn(o)) continue;
      leaf.setValueOnly(o, cache.inside(leaf.offsetToGlobalCoord(o)) ? -background : background);
    }
  });
}

}  // namespace

bool insideOfMesh(const InsideOutsideMesh& mesh, const WindingNumberField& closed,
                  const WindingNumberField& caps, const Eigen::Vector3d& point) {
  const std::optional<long> crossings =
      rayWindingNumber(closed.hierarchy(), mesh.points, mesh.triangles, point);
  if (!crossings) return closed.exact(point) - caps.exact(point) >= 0.5 - kClosingTie;
  const double w = static_cast<double>(*crossings);
  const double wS = caps.decide(point, [w](const WindingNumberField::Estimate& e) {
    return std::abs(w - e.value - 0.5) > e.errorBound;
  });
  return w - wS >= 0.5 - kClosingTie;
}

HoleCrossingReport coverHoleCrossings(openvdb::FloatGrid& grid, const InsideOutsideMesh& mesh,
                                      const WindingNumberField& closed,
                                      const WindingNumberField& caps) {
  HoleCrossingReport report;
  openvdb::FloatTree& tree = grid.tree();
  SideCache cache(mesh, closed, caps);
  const std::vector<Coord> members = crossingVoxels(tree, seedVoxels(tree, caps), cache);
  report.windingNumberQueries = cache.queries();
  if (members.empty()) return report;
  const float background = grid.background();
  const float magnitude = std::nextafter(background, 0.0f);
  {
    openvdb::tree::ValueAccessor<openvdb::FloatTree> accessor(tree);
    for (const Coord& c : members) {
      accessor.setValueOn(c, cache.inside(c) ? -magnitude : magnitude);
    }
  }
  setInactiveSides(tree, members, cache);
  // Tiles only (levels 1 and up): the leaves' inactive values are exact now.
  openvdb::tools::signedFloodFillWithValues(tree, background, -background, true, 1, 1);
  report.addedVoxels = members.size();
  report.windingNumberQueries = cache.queries();
  return report;
}

}  // namespace d2vdb::detail
