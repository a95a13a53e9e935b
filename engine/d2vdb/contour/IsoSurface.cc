// Parallel, deterministic marching cubes over the leaf blocks of a sparse grid (IsoSurface.h).
//
// Layout of the work: the "blocks" are the 8^3 cell blocks (cells named by their lowest corner)
// of every allocated leaf node and of the blocks just below one along any combination of axes, so
// every cell with a corner in a leaf is visited. Each crossed edge is owned by the block of the
// first visited cell around it (in a fixed order), which numbers it; the other blocks look its
// number up in the owner's sorted key list. Pass 1 counts vertices and triangles per block, a
// prefix sum gives every block its output ranges, pass 2 writes positions, normals and triangles
// straight into the output. Both passes recompute the block's values from the tree.
#include "d2vdb/contour/IsoSurface.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "d2vdb/contour/CubeTables.h"
#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

using contour::CubeTables;
using openvdb::Coord;

constexpr int kBlockSize = 8;
constexpr int kCornerSpan = kBlockSize + 1;  // corner layers 0..8 of a block's cells
constexpr int kEdgeKeyCount = 3 * kCornerSpan * kCornerSpan * kCornerSpan;
constexpr int kSelfSlot = 13;  // neighbourSlot(0, 0, 0)

/// Key of the edge from local corner (x, y, z) along `axis`; increasing in enumeration order.
inline int edgeKey(int x, int y, int z, int axis) {
  return ((x * kCornerSpan + y) * kCornerSpan + z) * 3 + axis;
}

/// Slot (0..26) of the neighbour block at offset (ox, oy, oz) in {-1, 0, 1}^3.
inline int neighbourSlot(int ox, int oy, int oz) {
  return (ox + 1) * 9 + (oy + 1) * 3 + (oz + 1);
}

/// Block offset along one axis of the cell at local coordinate q (-1..8).
inline int blockStep(int q) {
  return q < 0 ? -1 : (q >= kBlockSize ? 1 : 0);
}

/// The two axes other than `axis`, in increasing order.
inline std::array<int, 2> otherAxes(int axis) {
  return axis == 0 ? std::array<int, 2>{1, 2}
                   : (axis == 1 ? std::array<int, 2>{0, 2} : std::array<int, 2>{0, 1});
}

/// The sorted blocks to visit and, for each, its 27 neighbours (index or -1).
struct BlockSet {
  std::vector<Coord> origins;
  std::vector<std::array<std::int32_t, 27>> neighbours;
  std::vector<std::uint32_t> memberMask;  ///< bit slot set when that neighbour is a block
};

bool coordLess(const Coord& a, const Coord& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

/// Open-addressing map from block origin to block index (read-only after construction).
class BlockIndex {
 public:
  explicit BlockIndex(const std::vector<Coord>& origins) : origins_(origins) {
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
  std::int32_t find(const Coord& origin) const {
    for (std::size_t slot = hash(origin);; slot = (slot + 1) & mask_) {
      const std::int32_t index = slots_[slot];
      if (index == -1 || origins_[index] == origin) return index;
    }
  }

 private:
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

template <typename TreeT>
BlockSet collectBlocks(const TreeT& tree) {
  BlockSet set;
  std::vector<Coord> leafOrigins;
  leafOrigins.reserve(tree.leafCount());
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) leafOrigins.push_back(leaf->origin());
  set.origins.reserve(leafOrigins.size() * 4);
  for (const Coord& origin : leafOrigins) {
    for (int corner = 0; corner < 8; ++corner) {
      set.origins.push_back(origin - Coord((corner & 1) * kBlockSize,
                                           ((corner >> 1) & 1) * kBlockSize,
                                           ((corner >> 2) & 1) * kBlockSize));
    }
  }
  tbb::parallel_sort(set.origins.begin(), set.origins.end(), coordLess);
  set.origins.erase(std::unique(set.origins.begin(), set.origins.end()), set.origins.end());
  const BlockIndex index(set.origins);
  set.neighbours.resize(set.origins.size());
  set.memberMask.resize(set.origins.size());
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, set.origins.size(), 256),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
          std::uint32_t mask = 0;
          for (int ox = -1; ox <= 1; ++ox) {
            for (int oy = -1; oy <= 1; ++oy) {
              for (int oz = -1; oz <= 1; ++oz) {
                const int slot = neighbourSlot(ox, oy, oz);
                const std::int32_t found = index.find(
                    set.origins[b] + Coord(ox * kBlockSize, oy * kBlockSize, oz * kBlockSize));
                set.neighbours[b][slot] = found;
                if (found >= 0) mask |= 1u << slot;
              }
            }
          }
          set.memberMask[b] = mask;
        }
      });
  return set;
}

/// Corner values of one block's cells in local coordinates [lo, hi]^3 (x-major, z contiguous,
/// as in OpenVDB leaves), plus inside flags.
template <typename ValueT>
struct Region {
  int lo = 0, hi = kBlockSize, span = kCornerSpan;
  std::vector<ValueT> values;
  std::vector<std::uint8_t> inside;

  void configure(int low, int high) {
    lo = low;
    hi = high;
    span = hi - lo + 1;
    values.resize(static_cast<std::size_t>(span) * span * span);
    inside.resize(values.size());
  }
  int index(int x, int y, int z) const { return ((x - lo) * span + (y - lo)) * span + (z - lo); }
  ValueT value(int x, int y, int z) const { return values[index(x, y, z)]; }

  /// Reads the region of the block at `origin` through `accessor` and classifies it.
  template <typename AccessorT>
  void gather(AccessorT& accessor, const Coord& origin, double iso) {
    for (int ox = -1; ox <= 1; ++ox) {
      const int x0 = std::max(lo, ox * kBlockSize), x1 = std::min(hi, ox * kBlockSize + 7);
      if (x0 > x1) continue;
      for (int oy = -1; oy <= 1; ++oy) {
        const int y0 = std::max(lo, oy * kBlockSize), y1 = std::min(hi, oy * kBlockSize + 7);
        if (y0 > y1) continue;
        for (int oz = -1; oz <= 1; ++oz) {
          const int z0 = std::max(lo, oz * kBlockSize), z1 = std::min(hi, oz * kBlockSize + 7);
          if (z0 > z1) continue;
          const Coord neighbour = origin + Coord(ox * kBlockSize, oy * kBlockSize, oz * kBlockSize);
          if (const auto* leaf = accessor.probeConstLeaf(neighbour)) {
            const ValueT* data = leaf->buffer().data();
            for (int x = x0; x <= x1; ++x) {
              for (int y = y0; y <= y1; ++y) {
                const ValueT* source = data + ((x - ox * kBlockSize) << 6) +
                                       ((y - oy * kBlockSize) << 3) - oz * kBlockSize;
                ValueT* target = values.data() + index(x, y, 0);
                for (int z = z0; z <= z1; ++z) target[z] = source[z];
              }
            }
          } else {
            const ValueT fill = accessor.getValue(neighbour);
            for (int x = x0; x <= x1; ++x) {
              for (int y = y0; y <= y1; ++y) {
                ValueT* target = values.data() + index(x, y, 0);
                for (int z = z0; z <= z1; ++z) target[z] = fill;
              }
            }
          }
        }
      }
    }
    insideCount = 0;
    for (std::size_t i = 0; i < values.size(); ++i) {
      inside[i] = static_cast<double>(values[i]) < iso ? 1 : 0;
      insideCount += inside[i];
    }
  }

  /// True when every corner is on the same side (no crossing at all).
  bool uniform() const { return insideCount == 0 || insideCount == values.size(); }

  std::size_t insideCount = 0;
};

/// Visits, in increasing key order, every crossed edge of the block's cells:
/// visit(x, y, z, axis, ownerSlot, gap) with ownerSlot the neighbour slot of the owning block and
/// `gap` true when some but not all cells around the edge are visited (the surface leaves the
/// blocks there).
template <typename ValueT, typename Visit>
void forEachCrossedEdge(const Region<ValueT>& region, std::uint32_t memberMask, Visit&& visit) {
  static constexpr std::array<std::array<int, 2>, 4> kCandidates{{{0, 0}, {1, 0}, {0, 1}, {1, 1}}};
  for (int x = 0; x <= kBlockSize; ++x) {
    for (int y = 0; y <= kBlockSize; ++y) {
      for (int z = 0; z <= kBlockSize; ++z) {
        const int here = region.index(x, y, z);
        const std::array<int, 3> p{x, y, z};
        for (int axis = 0; axis < 3; ++axis) {
          if (p[axis] == kBlockSize) continue;
          const int stride = axis == 0 ? region.span * region.span : (axis == 1 ? region.span : 1);
          if (region.inside[here] == region.inside[here + stride]) continue;
          const auto [b, c] = otherAxes(axis);
          if (p[b] >= 1 && p[b] < kBlockSize && p[c] >= 1 && p[c] < kBlockSize) {
            visit(x, y, z, axis, kSelfSlot, false);
            continue;
          }
          int owner = -1;
          bool missing = false;
          for (const auto& candidate : kCandidates) {
            std::array<int, 3> step{0, 0, 0};
            step[b] = blockStep(p[b] - candidate[0]);
            step[c] = blockStep(p[c] - candidate[1]);
            const int slot = neighbourSlot(step[0], step[1], step[2]);
            if ((memberMask >> slot) & 1u) {
              if (owner < 0) owner = slot;
            } else {
              missing = true;
            }
          }
          visit(x, y, z, axis, owner, missing);
        }
      }
    }
  }
}

/// The corner offsets of the cell corners inside a region, indexed by corner number.
template <typename ValueT>
std::array<int, 8> cornerStrides(const Region<ValueT>& region) {
  std::array<int, 8> strides{};
  for (int corner = 0; corner < 8; ++corner) {
    const auto offset = contour::cornerOffset(corner);
    strides[corner] = (offset[0] * region.span + offset[1]) * region.span + offset[2];
  }
  return strides;
}

/// The face decisions (bit f: inside corners of ambiguous face f joined) of a cell.
template <typename ValueT>
std::uint8_t decideFaces(const Region<ValueT>& region, int base, const std::array<int, 8>& strides,
                         int caseIndex, std::uint8_t ambiguous, double iso) {
  static const std::array<std::array<int, 4>, 6> kFaceCorners = [] {
    std::array<std::array<int, 4>, 6> corners{};
    for (int face = 0; face < 6; ++face) corners[face] = contour::faceCorners(face);
    return corners;
  }();
  std::uint8_t joined = 0;
  for (int face = 0; face < 6; ++face) {
    if (((ambiguous >> face) & 1) == 0) continue;
    const auto& c = kFaceCorners[face];
    std::array<double, 4> relative{};
    for (int i = 0; i < 4; ++i) {
      relative[i] = static_cast<double>(region.values[base + strides[c[i]]]) - iso;
    }
    const double diagonal02 = relative[0] * relative[2], diagonal13 = relative[1] * relative[3];
    const bool corner0Inside = ((caseIndex >> c[0]) & 1) != 0;
    if (corner0Inside ? diagonal02 > diagonal13 : diagonal13 > diagonal02) joined |= 1u << face;
  }
  return joined;
}

template <typename ValueT>
int caseIndexAt(const Region<ValueT>& region, int base, const std::array<int, 8>& strides) {
  int caseIndex = 0;
  for (int corner = 0; corner < 8; ++corner)
    caseIndex |= region.inside[base + strides[corner]] << corner;
  return caseIndex;
}

/// Per-block results of pass 1.
struct BlockCounts {
  std::vector<std::uint16_t> ownedKeys;  ///< sorted keys of the edges the block numbers
  std::uint32_t centreVertices = 0;
  std::uint32_t triangles = 0;
  std::uint32_t gapEdges = 0;
  bool crossed = false;  ///< some edge of the block's cells is crossed
};

/// Runs body over [0, count) in parallel, in slices when progress is reported.
template <typename Body>
void forBlocks(std::size_t count, const char* stage, const ProgressCallback& progress,
               const Body& body) {
  const std::size_t slices = progress ? 20 : 1;
  for (std::size_t slice = 0; slice < slices; ++slice) {
    const std::size_t begin = count * slice / slices, end = count * (slice + 1) / slices;
    if (begin < end) tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 8), body);
    if (progress) progress(stage, static_cast<double>(end) / static_cast<double>(count));
  }
}

std::string formatNumber(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

template <typename GridT>
class Extractor {
  using ValueT = typename GridT::ValueType;

 public:
  Extractor(const GridT& grid, const IsoSurfaceOptions& options, const ProgressCallback& progress)
      : grid_(grid), options_(options), progress_(progress), tables_(CubeTables::instance()) {}

  TriangleMesh run() {
    checkIsoValue();
    blocks_ = collectBlocks(grid_.tree());
    const std::size_t blockCount = blocks_.origins.size();
    counts_.resize(blockCount);
    forBlocks(blockCount, "contour: counting", progress_,
              [this](const tbb::blocked_range<std::size_t>& range) { countBlocks(range); });

    vertexBase_.resize(blockCount + 1);
    triangleBase_.resize(blockCount + 1);
    std::uint64_t vertices = 0, triangles = 0, gaps = 0;
    for (std::size_t b = 0; b < blockCount; ++b) {
      vertexBase_[b] = vertices;
      triangleBase_[b] = triangles;
      vertices += counts_[b].ownedKeys.size() + counts_[b].centreVertices;
      triangles += counts_[b].triangles;
      gaps += counts_[b].gapEdges;
    }
    vertexBase_[blockCount] = vertices;
    triangleBase_[blockCount] = triangles;
    if (gaps > 0) throwOutsideBand(gaps);
    if (vertices > std::numeric_limits<TriangleMesh::Index>::max()) {
      throw RuntimeFailure("the iso-surface has " + std::to_string(vertices) +
                           " vertices, more than a mesh with 32-bit indices can hold");
    }

    mesh_.positions.resize(vertices);
    if (options_.computeNormals) mesh_.normals.resize(vertices);
    mesh_.triangles.resize(triangles);
    forBlocks(blockCount, "contour: meshing", progress_,
              [this](const tbb::blocked_range<std::size_t>& range) { meshBlocks(range); });
    return std::move(mesh_);
  }

 private:
  bool isLevelSet() const { return grid_.getGridClass() == openvdb::GRID_LEVEL_SET; }

  /// The largest |iso| a level set's band represents: background minus one voxel.
  double levelSetLimit() const {
    return std::abs(static_cast<double>(grid_.background())) - grid_.voxelSize()[0];
  }

  void checkIsoValue() const {
    if (!std::isfinite(options_.isoValue)) {
      throw InputError("the iso-value must be a finite number");
    }
    // Beyond this, some edge vertices would be interpolated from the background value instead
    // of a stored distance (the edge's far end lies outside the band).
    if (isLevelSet() && std::abs(options_.isoValue) > levelSetLimit()) throwOutsideBand(0);
  }

  [[noreturn]] void throwOutsideBand(std::uint64_t gapEdges) const {
    std::string message = "iso-value " + formatNumber(options_.isoValue) +
                          " lies outside what the grid's narrow band can represent";
    if (gapEdges > 0) {
      message += ": the iso-surface leaves the stored band at " + std::to_string(gapEdges) +
                 " cell edges, so the mesh would have holes";
    }
    if (isLevelSet()) {
      const double limit = levelSetLimit();
      message += (gapEdges > 0 ? "; this" : ": this") + std::string(" level set (background ") +
                 formatNumber(static_cast<double>(grid_.background())) + ", voxel size " +
                 formatNumber(grid_.voxelSize()[0]) +
                 ") holds iso-surfaces for |iso| up to about " +
                 formatNumber(std::max(0.0, limit)) +
                 " (background minus one voxel, so that both ends of every crossed edge hold "
                 "stored distances)";
      if (std::abs(options_.isoValue) > limit) {
        message += ", which this iso-value exceeds by " +
                   formatNumber(std::abs(options_.isoValue) - std::max(0.0, limit));
      }
      message += "; rebuild the level set with a wider band (--half-width)";
    }
    throw InputError(message + ".");
  }

  void countBlocks(const tbb::blocked_range<std::size_t>& range) {
    auto accessor = grid_.getConstAccessor();
    Region<ValueT> region;
    region.configure(0, kBlockSize);
    const auto strides = cornerStrides(region);
    const double iso = options_.isoValue;
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      region.gather(accessor, blocks_.origins[b], iso);
      if (region.uniform()) continue;
      BlockCounts& counts = counts_[b];
      forEachCrossedEdge(
          region, blocks_.memberMask[b], [&](int x, int y, int z, int axis, int owner, bool gap) {
            counts.crossed = true;
            if (owner != kSelfSlot) return;
            counts.ownedKeys.push_back(static_cast<std::uint16_t>(edgeKey(x, y, z, axis)));
            if (gap) ++counts.gapEdges;
          });
      if (!counts.crossed) continue;  // no crossed edge, no cell to triangulate
      for (int x = 0; x < kBlockSize; ++x) {
        for (int y = 0; y < kBlockSize; ++y) {
          for (int z = 0; z < kBlockSize; ++z) {
            const int base = region.index(x, y, z);
            const int caseIndex = caseIndexAt(region, base, strides);
            if (caseIndex == 0 || caseIndex == 255) continue;
            const std::uint8_t ambiguous = tables_.ambiguousFaces(caseIndex);
            const std::uint8_t joined =
                ambiguous ? decideFaces(region, base, strides, caseIndex, ambiguous, iso) : 0;
            const auto& cell = tables_.triangulation(caseIndex, joined);
            counts.triangles += cell.triangleCount;
            if (cell.centreEdges) ++counts.centreVertices;
          }
        }
      }
    }
  }

  /// Parameter of the vertex along an edge from value v0 to v1 (they straddle the iso-value).
  double edgeParameter(double v0, double v1) const {
    const double t = (options_.isoValue - v0) / (v1 - v0);
    if (options_.raw) return std::clamp(t, 0.0, 1.0);
    return std::clamp(t, kCornerClearance, 1.0 - kCornerClearance);
  }

  /// Index-space gradient at a region corner by central differences.
  openvdb::Vec3d cornerGradient(const Region<ValueT>& region, int x, int y, int z) const {
    return 0.5 * openvdb::Vec3d(
                     static_cast<double>(region.value(x + 1, y, z)) - region.value(x - 1, y, z),
                     static_cast<double>(region.value(x, y + 1, z)) - region.value(x, y - 1, z),
                     static_cast<double>(region.value(x, y, z + 1)) - region.value(x, y, z - 1));
  }

  Eigen::Vector3f worldNormal(const openvdb::Vec3d& indexGradient,
                              const openvdb::Vec3d& indexPosition, int fallbackAxis,
                              double fallbackSign) const {
    openvdb::Vec3d gradient = grid_.transform().baseMap()->applyIJT(indexGradient, indexPosition);
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

  Eigen::Vector3f worldPosition(const openvdb::Vec3d& indexPosition) const {
    const openvdb::Vec3d world = grid_.transform().indexToWorld(indexPosition);
    return Eigen::Vector3f(static_cast<float>(world[0]), static_cast<float>(world[1]),
                           static_cast<float>(world[2]));
  }

  /// Local index-space position of the vertex on the edge from (x, y, z) along `axis`.
  openvdb::Vec3d localEdgePoint(const Region<ValueT>& region, int x, int y, int z, int axis,
                                double* parameter = nullptr) const {
    std::array<int, 3> end{x, y, z};
    ++end[axis];
    const double t = edgeParameter(region.value(x, y, z), region.value(end[0], end[1], end[2]));
    if (parameter) *parameter = t;
    openvdb::Vec3d point(x, y, z);
    point[axis] += t;
    return point;
  }

  void meshBlocks(const tbb::blocked_range<std::size_t>& range) {
    auto accessor = grid_.getConstAccessor();
    Region<ValueT> region;
    const bool normals = options_.computeNormals;
    region.configure(normals ? -1 : 0, normals ? kBlockSize + 1 : kBlockSize);
    const auto strides = cornerStrides(region);
    const double iso = options_.isoValue;
    std::vector<TriangleMesh::Index> vertexOfEdge(kEdgeKeyCount);
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      const BlockCounts& counts = counts_[b];
      if (!counts.crossed) continue;
      const Coord origin = blocks_.origins[b];
      const openvdb::Vec3d originIndex(origin.x(), origin.y(), origin.z());
      region.gather(accessor, origin, iso);
      TriangleMesh::Index nextVertex = static_cast<TriangleMesh::Index>(vertexBase_[b]);
      forEachCrossedEdge(
          region, blocks_.memberMask[b], [&](int x, int y, int z, int axis, int owner, bool) {
            const int key = edgeKey(x, y, z, axis);
            if (owner == kSelfSlot) {
              const TriangleMesh::Index vertex = nextVertex++;
              vertexOfEdge[key] = vertex;
              double t = 0.0;
              const openvdb::Vec3d local = localEdgePoint(region, x, y, z, axis, &t);
              const openvdb::Vec3d indexPosition = originIndex + local;
              mesh_.positions[vertex] = worldPosition(indexPosition);
              if (normals) {
                std::array<int, 3> end{x, y, z};
                ++end[axis];
                const openvdb::Vec3d gradient = (1.0 - t) * cornerGradient(region, x, y, z) +
                                                t * cornerGradient(region, end[0], end[1], end[2]);
                const double sign =
                    region.value(end[0], end[1], end[2]) > region.value(x, y, z) ? 1.0 : -1.0;
                mesh_.normals[vertex] = worldNormal(gradient, indexPosition, axis, sign);
              }
              return;
            }
            vertexOfEdge[key] = lookUpVertex(b, owner, x, y, z, axis);
          });

      std::size_t nextTriangle = triangleBase_[b];
      for (int x = 0; x < kBlockSize; ++x) {
        for (int y = 0; y < kBlockSize; ++y) {
          for (int z = 0; z < kBlockSize; ++z) {
            const int base = region.index(x, y, z);
            const int caseIndex = caseIndexAt(region, base, strides);
            if (caseIndex == 0 || caseIndex == 255) continue;
            const std::uint8_t ambiguous = tables_.ambiguousFaces(caseIndex);
            const std::uint8_t joined =
                ambiguous ? decideFaces(region, base, strides, caseIndex, ambiguous, iso) : 0;
            const auto& cell = tables_.triangulation(caseIndex, joined);
            std::array<TriangleMesh::Index, 13> vertexOf{};
            for (int edge = 0; edge < contour::kCubeEdges; ++edge) {
              if (((tables_.crossedEdges(caseIndex) >> edge) & 1) == 0) continue;
              const auto start = contour::cornerOffset(contour::edgeStartCorner(edge));
              vertexOf[edge] = vertexOfEdge[edgeKey(x + start[0], y + start[1], z + start[2],
                                                    contour::edgeAxis(edge))];
            }
            if (cell.centreEdges) {
              vertexOf[contour::kCellCentre] = nextVertex++;
              writeCentreVertex(region, originIndex, x, y, z, cell.centreEdges,
                                vertexOf[contour::kCellCentre]);
            }
            for (int i = 0; i < cell.triangleCount; ++i) {
              mesh_.triangles[nextTriangle++] = {vertexOf[cell.edges[3 * i]],
                                                 vertexOf[cell.edges[3 * i + 1]],
                                                 vertexOf[cell.edges[3 * i + 2]]};
            }
          }
        }
      }
    }
  }

  /// The vertex of an edge numbered by the neighbour block in `ownerSlot`.
  TriangleMesh::Index lookUpVertex(std::size_t block, int ownerSlot, int x, int y, int z,
                                   int axis) const {
    const int ox = ownerSlot / 9 - 1, oy = (ownerSlot / 3) % 3 - 1, oz = ownerSlot % 3 - 1;
    const std::int32_t owner = blocks_.neighbours[block][ownerSlot];
    const auto& keys = counts_[owner].ownedKeys;
    const auto key = static_cast<std::uint16_t>(
        edgeKey(x - ox * kBlockSize, y - oy * kBlockSize, z - oz * kBlockSize, axis));
    const auto found = std::lower_bound(keys.begin(), keys.end(), key);
    if (found == keys.end() || *found != key) {
      throw RuntimeFailure("internal error in marching cubes: a shared edge has no vertex");
    }
    return static_cast<TriangleMesh::Index>(vertexBase_[owner] + (found - keys.begin()));
  }

  /// Places a cell's centre vertex at the mean of its contour's edge vertices; its normal is the
  /// gradient of the cell's trilinear interpolant there.
  void writeCentreVertex(const Region<ValueT>& region, const openvdb::Vec3d& originIndex, int x,
                         int y, int z, std::uint16_t edges, TriangleMesh::Index vertex) {
    openvdb::Vec3d sum(0.0);
    int count = 0;
    for (int edge = 0; edge < contour::kCubeEdges; ++edge) {
      if (((edges >> edge) & 1) == 0) continue;
      const auto start = contour::cornerOffset(contour::edgeStartCorner(edge));
      sum +=
          localEdgePoint(region, x + start[0], y + start[1], z + start[2], contour::edgeAxis(edge));
      ++count;
    }
    const openvdb::Vec3d local = sum / static_cast<double>(count);
    mesh_.positions[vertex] = worldPosition(originIndex + local);
    if (!options_.computeNormals) return;
    const double u = local[0] - x, v = local[1] - y, w = local[2] - z;
    const auto f = [&](int dx, int dy, int dz) {
      return static_cast<double>(region.value(x + dx, y + dy, z + dz));
    };
    const auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
    const openvdb::Vec3d gradient(
        lerp(lerp(f(1, 0, 0) - f(0, 0, 0), f(1, 1, 0) - f(0, 1, 0), v),
             lerp(f(1, 0, 1) - f(0, 0, 1), f(1, 1, 1) - f(0, 1, 1), v), w),
        lerp(lerp(f(0, 1, 0) - f(0, 0, 0), f(1, 1, 0) - f(1, 0, 0), u),
             lerp(f(0, 1, 1) - f(0, 0, 1), f(1, 1, 1) - f(1, 0, 1), u), w),
        lerp(lerp(f(0, 0, 1) - f(0, 0, 0), f(1, 0, 1) - f(1, 0, 0), u),
             lerp(f(0, 1, 1) - f(0, 1, 0), f(1, 1, 1) - f(1, 1, 0), u), v));
    mesh_.normals[vertex] = worldNormal(gradient, originIndex + local, 2, 1.0);
  }

  const GridT& grid_;
  const IsoSurfaceOptions& options_;
  const ProgressCallback& progress_;
  const CubeTables& tables_;
  BlockSet blocks_;
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
