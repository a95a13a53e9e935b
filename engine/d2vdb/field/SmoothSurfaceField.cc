// smoothSurfaceField(): seeds on the smooth surface, the band around them, and every band voxel
// projected onto the surface, starting from its neighbour's projection.
#include "d2vdb/field/SmoothSurfaceField.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/SmoothSurface.h"
#include "d2vdb/manifold/SourceDistance.h"

namespace d2vdb {
namespace {

using Index = HalfEdgeMesh::Index;

/// Largest distance between neighbouring lattice points of one face (positions in faceLattice
/// order for `intervals` intervals per edge).
double largestLatticeStep(const std::vector<Eigen::Vector3d>& points, long intervals) {
  double largest = 0.0;
  std::size_t index = 0;
  std::vector<std::size_t> rowStart;
  for (long i = 0; i <= intervals; ++i) {
    rowStart.push_back(index);
    index += static_cast<std::size_t>(intervals - i + 1);
  }
  const auto at = [&](long i, long j) { return points[rowStart[i] + static_cast<std::size_t>(j)]; };
  for (long i = 0; i <= intervals; ++i) {
    for (long j = 0; i + j <= intervals; ++j) {
      if (i + j < intervals) {
        largest = std::max(largest, (at(i + 1, j) - at(i, j)).norm());
        largest = std::max(largest, (at(i, j + 1) - at(i, j)).norm());
      }
      if (i > 0 && i + j <= intervals) {
        largest = std::max(largest, (at(i - 1, j + 1) - at(i, j)).norm());
      }
    }
  }
  return largest;
}

/// The smallest squared distance from q to the points (xs, ys, zs) (count a multiple of 8, at
/// least 8) and the first position where it occurs. The points are taken in 8 lanes (position
/// mod 8), each keeping its minimum and the first position of it; then the lanes' first position
/// of the overall minimum. Branch-free, vectorised.
struct LaneMinimum {
  float squared;
  std::int32_t first;
};

/// The lanes' minima to the answer (the smallest value, then the first position).
template <typename Values, typename Positions>
LaneMinimum reduceLanes(const Values& values, const Positions& positions) {
  LaneMinimum result{values(0), positions(0)};
  for (int j = 1; j < 8; ++j) {
    if (values(j) < result.squared ||
        (values(j) == result.squared && positions(j) < result.first)) {
      result.squared = values(j);
      result.first = positions(j);
    }
  }
  return result;
}

/// Four floats / four 32-bit integers in one SSE register (GCC/Clang vector extension).
typedef float Floats4 __attribute__((vector_size(16), aligned(4), may_alias));
typedef std::int32_t Ints4 __attribute__((vector_size(16)));

/// nearestInLanes with two groups of four lanes (SSE2).
LaneMinimum nearestInLanes4(const float* xs, const float* ys, const float* zs, std::size_t count,
                            float qx, float qy, float qz) {
  constexpr float kFar = std::numeric_limits<float>::infinity();
  Floats4 lanes[2] = {Floats4{} + kFar, Floats4{} + kFar};
  Ints4 at[2] = {Ints4{0, 1, 2, 3}, Ints4{4, 5, 6, 7}};
  Ints4 position[2] = {Ints4{0, 1, 2, 3}, Ints4{4, 5, 6, 7}};
  for (std::size_t i = 0; i < count; i += 8) {
    for (int g = 0; g < 2; ++g) {
      const std::size_t k = i + 4 * static_cast<std::size_t>(g);
      const Floats4 dx = *reinterpret_cast<const Floats4*>(xs + k) - qx;
      const Floats4 dy = *reinterpret_cast<const Floats4*>(ys + k) - qy;
      const Floats4 dz = *reinterpret_cast<const Floats4*>(zs + k) - qz;
      const Floats4 squared = dx * dx + dy * dy + dz * dz;
      const Ints4 lower = squared < lanes[g];
      lanes[g] = lower ? squared : lanes[g];
      at[g] = lower ? position[g] : at[g];
      position[g] += 8;
    }
  }
  return reduceLanes([&](int j) { return lanes[j / 4][j % 4]; },
                     [&](int j) { return at[j / 4][j % 4]; });
}

#if defined(__GNUC__) && defined(__x86_64__)
#define D2VDB_WIDE_NEAREST 1
typedef float Floats8 __attribute__((vector_size(32), aligned(4), may_alias));
typedef std::int32_t Ints8 __attribute__((vector_size(32)));

/// nearestInLanes with all eight lanes in one AVX2 register: the same lanes, the same operations
/// on each, so the same answer to the bit.
__attribute__((target("avx2"))) LaneMinimum nearestInLanes8(const float* xs, const float* ys,
                                                            const float* zs, std::size_t count,
                                                            float qx, float qy, float qz) {
  constexpr float kFar = std::numeric_limits<float>::infinity();
  Floats8 lanes = Floats8{} + kFar;
  Ints8 at = Ints8{0, 1, 2, 3, 4, 5, 6, 7};
  Ints8 position = at;
  for (std::size_t i = 0; i < count; i += 8) {
    const Floats8 dx = *reinterpret_cast<const Floats8*>(xs + i) - qx;
    const Floats8 dy = *reinterpret_cast<const Floats8*>(ys + i) - qy;
    const Floats8 dz = *reinterpret_cast<const Floats8*>(zs + i) - qz;
    const Floats8 squared = dx * dx + dy * dy + dz * dz;
    const Ints8 lower = squared < lanes;
    lanes = lower ? squared : lanes;
    at = lower ? position : at;
    position += 8;
  }
  return reduceLanes([&](int j) { return lanes[j]; }, [&](int j) { return at[j]; });
}
#endif

LaneMinimum nearestInLanes(const float* xs, const float* ys, const float* zs, std::size_t count,
                           float qx, float qy, float qz) {
#ifdef D2VDB_WIDE_NEAREST
  static const bool wide = __builtin_cpu_supports("avx2");
  if (wide) return nearestInLanes8(xs, ys, zs, count, qx, qy, qz);
#endif
  return nearestInLanes4(xs, ys, zs, count, qx, qy, qz);
}

/// Surface seeds grouped by the leaf-node block (8^3 voxels) of the voxel they lie in, for exact
/// nearest-seed queries near one leaf at a time.
class SeedBlocks {
 public:
  /// The nearest seed of a query: its index in the constructor's vector and its distance
  /// (infinite when no seed lies within the radius near() was given).
  struct Nearest {
    std::uint32_t index = 0;
    double distance = std::numeric_limits<double>::infinity();
    /// The seed's position, to float precision of its offset from the leaf (the list's copy,
    /// which is in cache, unlike the seed array).
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
  };

  /// The seeds within a radius of one leaf's voxel centres, as float offsets from the leaf's
  /// first voxel centre (structure of arrays, so the distance loop vectorises).
  class Near {
   public:
    /// The nearest of these seeds to `point` (ties to the first in the list), exact for seeds
    /// within the radius; infinite distance when there is none that near.
    Nearest nearest(const Eigen::Vector3d& point) const {
      Nearest result;
      if (count_ == 0) return result;
      const Eigen::Vector3f q = (point - origin_).cast<float>();
      // The first position of the smallest distance (nearestInLanes; the arrays are padded to a
      // multiple of kLanes with far-away points; the list's order depends only on the leaf).
      const LaneMinimum minimum =
          nearestInLanes(xs_.data(), ys_.data(), zs_.data(), padded(), q.x(), q.y(), q.z());
      const float best = minimum.squared;
      const std::int32_t first = minimum.first;
      const std::uint32_t bestIndex = index_[static_cast<std::size_t>(first)];
      if (static_cast<double>(best) > radius2_) return result;
      const auto at = static_cast<std::size_t>(first);
      result.index = bestIndex;
      result.distance = std::sqrt(static_cast<double>(best));
      result.position = origin_ + Eigen::Vector3f(xs_[at], ys_[at], zs_[at]).cast<double>();
      return result;
    }

   private:
    friend class SeedBlocks;
    static constexpr std::size_t kLanes = 8;
    /// The count rounded up to whole lanes.
    std::size_t padded() const { return (count_ + kLanes - 1) / kLanes * kLanes; }
    /// Empties the list and makes room for `seeds` seeds and the padding (the arrays only grow,
    /// so a worker's lists stop allocating after its first leaves).
    void reset(std::size_t seeds) {
      count_ = 0;
      if (xs_.size() < seeds + kLanes) {
        const std::size_t size = 2 * (seeds + kLanes);
        xs_.resize(size);
        ys_.resize(size);
        zs_.resize(size);
        index_.resize(size);
      }
    }
    /// Pads the arrays to whole lanes with points far beyond any query (never the nearest).
    void pad() {
      for (std::size_t i = count_; i < padded(); ++i) {
        xs_[i] = std::numeric_limits<float>::max();
        ys_[i] = 0.0f;
        zs_[i] = 0.0f;
        index_[i] = 0;
      }
    }
    Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
    double radius2_ = 0.0;
    std::size_t count_ = 0;  ///< seeds in the list (the arrays are longer)
    std::vector<float> xs_, ys_, zs_;
    std::vector<std::uint32_t> index_;
  };

  SeedBlocks(const std::vector<Eigen::Vector3d>& seeds, double voxelSize) : voxelSize_(voxelSize) {
    std::vector<std::pair<openvdb::Coord, std::uint32_t>> keyed(seeds.size());
    tbb::parallel_for(std::size_t{0}, seeds.size(), [&](std::size_t i) {
      keyed[i] = {blockOf(seeds[i]), static_cast<std::uint32_t>(i)};
    });
    tbb::parallel_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first < b.first : a.second < b.second;
    });
    order_.resize(keyed.size());
    positions_.resize(keyed.size());
    tbb::parallel_for(std::size_t{0}, keyed.size(), [&](std::size_t i) {
      order_[i] = keyed[i].second;
      positions_[i] = seeds[keyed[i].second];
    });
    // Each block's run of seeds, entered once at its end.
    std::size_t first = 0;
    for (std::size_t i = 1; i <= keyed.size(); ++i) {
      if (i == keyed.size() || keyed[i].first != keyed[first].first) {
        ranges_.emplace(keyed[first].first, std::make_pair(first, i));
        first = i;
      }
    }
  }

  /// Fills parts[b] with the seeds within `radius` of the voxel centres of sub-block b of the
  /// leaf at `origin` (a multiple of 8 in every coordinate): its eight 4^3 sub-blocks, b = 4
  /// [x >= 4] + 2 [y >= 4] + [z >= 4], each list in the order of the blocks (dx, dy, dz) and
  /// of the seeds' indices in them. One pass over the seeds of the blocks that can hold them: a
  /// test against the leaf's box (doubles), then against each sub-block's (float offsets from
  /// the leaf's first voxel centre, the parts' coordinates).
  void near(const openvdb::Coord& origin, double radius, Near (&parts)[8]) const {
    const Eigen::Vector3d leafOrigin =
        Eigen::Vector3d(origin.x(), origin.y(), origin.z()) * voxelSize_;
    const openvdb::Coord block(origin.x() >> 3, origin.y() >> 3, origin.z() >> 3);
    // A seed is in the block of its nearest voxel, within half a voxel of it: the blocks of
    // the seeds within `radius` (plus the margin below) of the leaf's voxel centres lie within
    // `reach` blocks of the leaf's.
    const int reach = static_cast<int>(std::ceil((radius / voxelSize_ + 0.501) / 8.0));
    std::vector<std::pair<std::size_t, std::size_t>> ranges;
    const std::size_t seeds = blockRanges(block, reach, ranges);
    for (Near& part : parts) {
      part.origin_ = leafOrigin;
      part.radius2_ = radius * radius;
      part.reset(seeds);
    }
    const Eigen::Vector3d lo = leafOrigin;
    const Eigen::Vector3d hi = leafOrigin + Eigen::Vector3d::Constant(7.0 * voxelSize_);
    // Slightly beyond the radius, so that float rounding of the offsets loses no seed the
    // nearest-seed test could need.
    const double margin = radius + 1e-3 * voxelSize_;
    const double keep = margin * margin;
    // (The sub-blocks' bound from the squared radius, as the parts store it.)
    const double partMargin = std::sqrt(radius * radius) + 1e-3 * voxelSize_;
    const auto keepFloat = static_cast<float>(partMargin * partMargin);
    // Sub-block b spans voxel offsets 0..3 or 4..7 along each axis.
    const auto f = [&](int offset) { return static_cast<float>(offset * voxelSize_); };
    const float low[2] = {f(0), f(4)};
    const float high[2] = {f(3), f(7)};
    const auto squaredGap = [&](float p, int half) {
      const float gap = std::max(std::max(low[half] - p, p - high[half]), 0.0f);
      return gap * gap;
    };
    // Each seed is written to every part and counted in those it belongs to (no branch).
    std::size_t counts[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (const auto& [first, last] : ranges) {
      for (std::size_t i = first; i < last; ++i) {
        const Eigen::Vector3d& p = positions_[i];
        const Eigen::Vector3d gap = (lo - p).cwiseMax(p - hi).cwiseMax(Eigen::Vector3d::Zero());
        if (gap.squaredNorm() > keep) continue;
        const Eigen::Vector3f offset = (p - leafOrigin).cast<float>();
        const float x = offset.x(), y = offset.y(), z = offset.z();
        const float gx[2] = {squaredGap(x, 0), squaredGap(x, 1)};
        const float gy[2] = {squaredGap(y, 0), squaredGap(y, 1)};
        const float gz[2] = {squaredGap(z, 0), squaredGap(z, 1)};
        const std::uint32_t index = order_[i];
        for (int b = 0; b < 8; ++b) {
          Near& part = parts[b];
          const std::size_t at = counts[b];
          part.xs_[at] = x;
          part.ys_[at] = y;
          part.zs_[at] = z;
          part.index_[at] = index;
          counts[b] += gx[b >> 2] + gy[(b >> 1) & 1] + gz[b & 1] > keepFloat ? 0 : 1;
        }
      }
    }
    for (int b = 0; b < 8; ++b) parts[b].count_ = counts[b];
    for (Near& part : parts) part.pad();
  }

 private:
  /// Appends the ranges (into order_ and positions_) of the seed blocks within `reach` blocks of
  /// `block` along every axis to `ranges`, in (dx, dy, dz) order; returns their number of seeds.
  std::size_t blockRanges(const openvdb::Coord& block, int reach,
                          std::vector<std::pair<std::size_t, std::size_t>>& ranges) const {
    std::size_t seeds = 0;
    for (int dx = -reach; dx <= reach; ++dx) {
      for (int dy = -reach; dy <= reach; ++dy) {
        for (int dz = -reach; dz <= reach; ++dz) {
          const auto found = ranges_.find(block.offsetBy(dx, dy, dz));
          if (found == ranges_.end()) continue;
          ranges.push_back(found->second);
          seeds += found->second.second - found->second.first;
        }
      }
    }
    return seeds;
  }

  openvdb::Coord blockOf(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d index = p / voxelSize_;
    const openvdb::Coord voxel(static_cast<int>(std::lround(index.x())),
                               static_cast<int>(std::lround(index.y())),
                               static_cast<int>(std::lround(index.z())));
    return {voxel.x() >> 3, voxel.y() >> 3, voxel.z() >> 3};
  }

  double voxelSize_;
  std::vector<std::uint32_t> order_;        ///< seed indices, sorted by block and index
  std::vector<Eigen::Vector3d> positions_;  ///< in that order
  std::unordered_map<openvdb::Coord, std::pair<std::size_t, std::size_t>> ranges_;
};

/// Displacements (within a leaf) of the voxels a voxel's projection may start from: the face
/// neighbours at -z, -y, -x (the first kFaceNeighbors), then the edge and corner neighbours among
/// the voxels visited before it in offset order (x, then y, then z ascending).
constexpr std::array<std::array<int, 3>, 13> kStartNeighbors = {{{0, 0, -1},
                                                                 {0, -1, 0},
                                                                 {-1, 0, 0},
                                                                 {0, -1, -1},
                                                                 {0, -1, 1},
                                                                 {-1, 0, -1},
                                                                 {-1, 0, 1},
                                                                 {-1, -1, 0},
                                                                 {-1, 1, 0},
                                                                 {-1, -1, -1},
                                                                 {-1, -1, 1},
                                                                 {-1, 1, -1},
                                                                 {-1, 1, 1}}};
constexpr std::size_t kFaceNeighbors = 3;

/// The number of lattice points of faces with these intervals per edge.
double latticePointCount(const std::vector<long>& intervals) {
  double count = 0.0;
  for (const long g : intervals) count += 0.5 * static_cast<double>(g + 1) * (g + 2);
  return count;
}

/// Pilot intervals per face edge from the mesh's edge lengths: half as dense as `spacing` asks
/// for flat faces.
std::vector<long> pilotIntervals(const HalfEdgeMesh& mesh, double spacing) {
  const std::size_t faceCount = mesh.faceCount();
  std::vector<long> intervals(faceCount);
  tbb::parallel_for(std::size_t{0}, faceCount, [&](std::size_t f) {
    const auto face = static_cast<Index>(f);
    double extent = 0.0;
    for (int k = 0; k < 3; ++k) {
      extent = std::max(extent, (mesh.position(mesh.corner(face, k)) -
                                 mesh.position(mesh.corner(face, (k + 1) % 3)))
                                    .norm());
    }
    intervals[f] = std::max(1L, static_cast<long>(std::ceil(0.5 * extent / spacing)));
  });
  return intervals;
}

/// Raises each face's intervals until the largest step between neighbouring lattice points on
/// the surface is within `spacing`: from the largest step of the lattice so far, to the intervals
/// that bring it within `spacing` (the steps shrink about in proportion to the intervals), at most
/// 8 rounds. facePositions[f] receives the surface points of face f's final lattice. Throws
/// InputError when more than `seedBudget` points would be needed or a face is not done then.
void refineLattices(const PseudoManifold& surface, double spacing, double seedBudget,
                    double voxelSize, std::vector<long>& intervals,
                    std::vector<std::vector<Eigen::Vector3d>>& facePositions) {
  const std::size_t faceCount = intervals.size();
  // One byte per face, not std::vector<bool>: the faces' tasks write their flags concurrently, and
  // neighbouring bits of a bit vector share a word (a data race ThreadSanitizer reports).
  std::vector<std::uint8_t> done(faceCount, 0);
  const auto allDone = [&] {
    return std::all_of(done.begin(), done.end(), [](std::uint8_t d) { return d != 0; });
  };
  for (int round = 0; round < 8; ++round) {
    if (latticePointCount(intervals) > seedBudget) {
      throw InputError("smooth-surface field: " + std::to_string(latticePointCount(intervals)) +
                       " surface seeds would be needed at voxel size " + std::to_string(voxelSize) +
                       ", more than the budget of " + std::to_string(seedBudget) +
                       "; choose a coarser voxel size");
    }
    tbb::parallel_for(std::size_t{0}, faceCount, [&](std::size_t f) {
      if (done[f]) return;
      const auto face = static_cast<Index>(f);
      const std::vector<Eigen::Vector3d> lattice = faceLattice(static_cast<int>(intervals[f]));
      std::vector<Eigen::Vector3d>& points = facePositions[f];
      points.resize(lattice.size());
      for (std::size_t i = 0; i < lattice.size(); ++i)
        points[i] = surface.position({face, lattice[i]});
      const double largest = largestLatticeStep(points, intervals[f]);
      if (largest <= spacing) {
        done[f] = 1;
      } else {
        // Scaled by the excess and 5 % more, by at least one interval.
        const double scaled =
            std::ceil(static_cast<double>(intervals[f]) * 1.05 * largest / spacing);
        intervals[f] = std::max(intervals[f] + 1, static_cast<long>(std::min(scaled, 1e6)));
      }
    });
    if (allDone()) break;
  }
  if (!allDone()) {
    throw InputError("smooth-surface field: the surface could not be sampled at voxel size " +
                     std::to_string(voxelSize) + " (a face stretches too far)");
  }
}

/// Surface seeds: points of the smooth surface and the face points they are at.
struct SurfaceSeeds {
  std::vector<Eigen::Vector3d> positions;
  std::vector<FacePoint> points;
};

/// The seeds of every face's lattice at most `spacing` apart on the surface (refineLattices),
/// face by face in lattice order.
SurfaceSeeds surfaceSeeds(const PseudoManifold& surface, double spacing, double seedBudget,
                          double voxelSize) {
  const std::size_t faceCount = surface.mesh().faceCount();
  std::vector<long> intervals = pilotIntervals(surface.mesh(), spacing);
  std::vector<std::vector<Eigen::Vector3d>> facePositions(faceCount);
  refineLattices(surface, spacing, seedBudget, voxelSize, intervals, facePositions);
  // The seeds face by face (each face's from its offset on), in parallel.
  std::vector<std::size_t> seedOffset(faceCount + 1, 0);
  for (std::size_t f = 0; f < faceCount; ++f)
    seedOffset[f + 1] = seedOffset[f] + facePositions[f].size();
  SurfaceSeeds seeds;
  seeds.positions.resize(seedOffset[faceCount]);
  seeds.points.resize(seedOffset[faceCount]);
  tbb::parallel_for(std::size_t{0}, faceCount, [&](std::size_t f) {
    const std::vector<Eigen::Vector3d> lattice = faceLattice(static_cast<int>(intervals[f]));
    for (std::size_t i = 0; i < lattice.size(); ++i) {
      seeds.positions[seedOffset[f] + i] = facePositions[f][i];
      seeds.points[seedOffset[f] + i] = {static_cast<Index>(f), lattice[i]};
    }
    std::vector<Eigen::Vector3d>().swap(facePositions[f]);
  });
  return seeds;
}

/// How the band voxels are projected (PseudoManifold::project), stopping beyond `stopBeyond`
/// (world units).
SmoothProjectionOptions bandProjectionOptions(double stopBeyond) {
  // The field stores curvatures in half precision: their O(1e-6) error from an extrapolated last
  // step does not show.
  SmoothProjectionOptions options;
  options.extrapolateLastStep = true;
  // Likewise their error of about 1e-5 of their value from a footpoint placed on the cubic
  // Taylor model of the surface at the last iterate (a step of at most 1e-3 of the chart radius
  // away), and from each voxel's start on its neighbour's model: most voxels then cost one
  // surface evaluation (with third derivatives), some none.
  options.cubicFinish = true;
  options.startFromModel = true;
  // Voxels certainly beyond the band are discarded without converging.
  options.stopBeyond = stopBeyond;
  return options;
}

/// The approximant of a voxel outside the band: its `distance`, above the half-width (the band
/// discards it).
Approximant outsideBand(const Eigen::Vector3d& center, double distance) {
  Approximant outside;
  outside.kind = TargetKind::Surface;
  outside.origin = center;
  outside.distance = distance;
  return outside;
}

/// What the voxel function keeps from one voxel to the next: everything depends only on the
/// current leaf node (8^3 voxels, visited in offset order, all in one call sequence), so the field
/// does not depend on the order of the leaves or the thread count: the seeds within skipBeyond of
/// the leaf (the nearest seed of a voxel, ties to the lowest index, is exact up to that distance),
/// and the projections of the leaf's voxels: each voxel's Newton iteration starts from a projected
/// neighbour visited before it in the same leaf (kStartNeighbors). One per thread, kept from one
/// block of leaves to the next, so that its buffers (0.4 MB) are allocated once per thread.
struct LeafState {
  openvdb::Coord leaf = openvdb::Coord::max();
  std::uint32_t generation = 0;
  std::vector<std::uint32_t> stamp = std::vector<std::uint32_t>(512, 0);
  std::vector<PseudoManifold::Projection> projections =
      std::vector<PseudoManifold::Projection>(512);
  // The neighbour each voxel's projection started from (1 + its index in kStartNeighbors), 0
  // for a start from a seed.
  std::vector<std::uint8_t> startedFrom = std::vector<std::uint8_t>(512, 0);
  SeedBlocks::Near subNear[8];  // the seeds near each of the leaf's 4^3 sub-blocks
};

/// The approximant of a candidate voxel of the smooth-surface field (smoothSurfaceField()), with
/// the state of its thread. Shared by every worker; immutable.
class VoxelProjector {
 public:
  /// `blocks` and `seeds` as surfaceSeeds() made them, seedReach (world units) the largest
  /// distance of a surface point from its nearest seed.
  VoxelProjector(const PseudoManifold& surface, const SeedBlocks& blocks,
                 const std::vector<FacePoint>& seeds, double voxelSize, double halfWidth,
                 double seedReach)
      : surface_(surface),
        blocks_(blocks),
        seeds_(seeds),
        options_(bandProjectionOptions(halfWidth * voxelSize)),
        seedReach_(seedReach),
        skipBeyond_(halfWidth * voxelSize + seedReach),
        sameSheet_(1.5 * seedReach),
        clamp_(1.0 / voxelSize) {}

  Approximant operator()(LeafState& state, const openvdb::Coord& ijk,
                         const Eigen::Vector3d& center) const {
    const openvdb::Coord leaf(ijk.x() & ~7, ijk.y() & ~7, ijk.z() & ~7);
    if (leaf != state.leaf) {
      state.leaf = leaf;
      ++state.generation;
      blocks_.near(leaf, skipBeyond_, state.subNear);
    }
    const int sub = ((ijk.x() & 4) >> 0) | ((ijk.y() & 4) >> 1) | ((ijk.z() & 4) >> 2);
    const SeedBlocks::Nearest nearest = state.subNear[sub].nearest(center);
    if (!(nearest.distance <= skipBeyond_)) {
      // Outside the band (a lower bound of the distance).
      return outsideBand(center, std::isfinite(nearest.distance) ? nearest.distance - seedReach_
                                                                 : skipBeyond_ - seedReach_);
    }
    const int offset = ((ijk.x() & 7) << 6) | ((ijk.y() & 7) << 3) | (ijk.z() & 7);
    // The voxel's projection goes straight into its slot (the leaf's earlier voxels, the
    // neighbour among them, have other slots).
    const auto at = static_cast<std::size_t>(offset);
    PseudoManifold::Projection& projection = state.projections[at];
    state.startedFrom[at] =
        project(state, startOf(state, ijk, offset, center), center, nearest, projection);
    state.stamp[at] = state.generation;
    if (projection.beyond) {
      // Outside the band (its distance is above the half-width). Its last iterate still starts
      // its neighbours' projections.
      return outsideBand(center, projection.distance);
    }
    Approximant a = SmoothSurface::approximantOf(center, projection);
    if (std::abs(a.k1) > clamp_ || std::abs(a.k2) > clamp_) {
      a.k1 = std::clamp(a.k1, -clamp_, clamp_);
      a.k2 = std::clamp(a.k2, -clamp_, clamp_);
      a.flags |= kFlagCurvatureClamped;
    }
    return a;
  }

 private:
  /// A voxel's start: the slot of the neighbour whose projection it starts from (-1: the
  /// nearest seed) and LeafState::startedFrom for it.
  struct Start {
    int neighbor = -1;
    std::uint8_t startedFrom = 0;
  };

  /// The neighbour to start from: of the face neighbours whose projection ended on a cubic
  /// model, the one whose model is expanded nearest to this voxel's centre (its footpoint is then
  /// mostly the nearest to this voxel's: the shortest step along the model, the most accurate
  /// start, the fewest evaluations); without one, the first of the other kStartNeighbors with a
  /// model; else the first projected neighbour (a Newton iteration from its footpoint); else
  /// none (a seed).
  Start startOf(const LeafState& state, const openvdb::Coord& ijk, int offset,
                const Eigen::Vector3d& center) const {
    Start start;
    // The slot of kStartNeighbors[k] when it lies in the leaf and was projected, else -1.
    const int x = ijk.x() & 7, y = ijk.y() & 7, z = ijk.z() & 7;
    const auto projectedSlot = [&](std::size_t k) {
      const auto& [dx, dy, dz] = kStartNeighbors[k];
      if (x + dx < 0 || y + dy < 0 || z + dz < 0 || y + dy > 7 || z + dz > 7) return -1;
      const int slot = offset + 64 * dx + 8 * dy + dz;
      return state.stamp[static_cast<std::size_t>(slot)] == state.generation ? slot : -1;
    };
    double nearestOrigin = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < kFaceNeighbors; ++k) {
      const int candidate = projectedSlot(k);
      if (candidate < 0) continue;
      const auto& model = state.projections[static_cast<std::size_t>(candidate)].model;
      if (!model) continue;
      const double squared = (model->derivatives.position - center).squaredNorm();
      if (squared < nearestOrigin) {
        nearestOrigin = squared;
        start = {candidate, static_cast<std::uint8_t>(k + 1)};
      }
    }
    const bool modeledFace = start.neighbor >= 0;
    for (std::size_t k = 0; k < kStartNeighbors.size() && !modeledFace; ++k) {
      const int candidate = projectedSlot(k);
      if (candidate < 0) continue;
      const bool modeled = state.projections[static_cast<std::size_t>(candidate)].model.has_value();
      if (start.neighbor < 0 || modeled) start = {candidate, static_cast<std::uint8_t>(k + 1)};
      if (modeled) break;
    }
    return start;
  }

  /// Projects `center` into `projection` from `start` (or from the nearest seed); returns the
  /// start it kept (LeafState::startedFrom).
  std::uint8_t project(const LeafState& state, const Start& start, const Eigen::Vector3d& center,
                       const SeedBlocks::Nearest& nearest,
                       PseudoManifold::Projection& projection) const {
    if (start.neighbor < 0) {
      projection = surface_.project(center, seeds_[nearest.index], options_);
      return start.startedFrom;
    }
    // Second-order start: when the neighbour was itself projected from its neighbour by the same
    // displacement, the first Newton step here misses the footpoint by nearly what the
    // neighbour's missed it by.
    const auto from = static_cast<std::size_t>(start.neighbor);
    SmoothProjectionOptions options = options_;
    if (state.startedFrom[from] == start.startedFrom) {
      options.firstStepCorrection = state.projections[from].firstStepMiss;
    }
    surface_.project(center, state.projections[from], options, projection);
    // A surface point (the nearest seed) is nearer than the local minimum found from the
    // neighbour, or the nearest seed lies on another sheet: that minimum may not be the closest
    // point (the voxel is near the medial axis); project from the seed too and keep the nearer.
    const bool elsewhere = projection.distance > nearest.distance ||
                           (nearest.position - projection.position).norm() > sameSheet_;
    if (elsewhere) {
      PseudoManifold::Projection fromSeed =
          surface_.project(center, seeds_[nearest.index], options_);
      if (fromSeed.distance < projection.distance) {
        projection = std::move(fromSeed);
        return 0;
      }
    }
    return start.startedFrom;
  }

  const PseudoManifold& surface_;
  const SeedBlocks& blocks_;
  const std::vector<FacePoint>& seeds_;
  const SmoothProjectionOptions options_;
  const double seedReach_;
  const double skipBeyond_;  ///< voxels whose nearest seed is further cannot be in the band
  /// A projection from the neighbour's footpoint is repeated from the nearest seed when that seed
  /// may stand for a nearer part of the surface: when it is nearer than the local minimum found
  /// (or the iterate, for a projection stopped beyond the band) or further than this from its
  /// surface point (the nearest seeds of its own sheet lie within seedReach of the footpoint, a
  /// stopped iterate within a few hundredths of a voxel of that): then the nearest seed lies on
  /// another sheet, which may be nearer than that seed by up to about seedReach^2 / (2 distance).
  const double sameSheet_;
  const double clamp_;  ///< curvatures are clamped to 1 / voxel
};

}  // namespace

ApproximantField smoothSurfaceField(const PseudoManifold& surface, double voxelSize,
                                    double halfWidth, const std::string& label,
                                    const ApproximantFieldOptions& options,
                                    const ProgressCallback& progress) {
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) {
    throw InputError("smooth-surface field: the voxel size must be a positive number");
  }
  if (!(halfWidth >= 1.0 && halfWidth <= 64.0)) {
    throw InputError("smooth-surface field: the half-width must lie in 1..64 voxels");
  }
  // Seeds at most 1.2 voxels apart: they find the band and start the projections of the first
  // voxels of each leaf. Denser seeds cost surface evaluations and nearest-seed scans for the
  // same band; sparser ones let more voxels beyond the band through the nearest-seed test and
  // weaken the medial-axis test (VoxelProjector::sameSheet_: it misses a nearer sheet whose seeds
  // are all further than a seed near the local minimum found). 1.2 was the fastest spacing
  // (BENCHMARKS.md, "Sparser seeds, a state per thread").
  const double spacing = 1.2 * voxelSize;
  const double seedBudget = 4.0 * static_cast<double>(options.maxActiveVoxels);
  SurfaceSeeds seeds = surfaceSeeds(surface, spacing, seedBudget, voxelSize);
  // The seeds by leaf-node block (8^3 voxels; block of voxel (i, j, k): (i, j, k) >> 3), sorted
  // by block and index, for the seeds near each leaf (SeedBlocks).
  const SeedBlocks blocks(seeds.positions, voxelSize);

  // Every surface point lies within `seedReach` of a seed: the corners of its lattice triangle
  // are at most `spacing` apart, every point of a flat triangle whose edges are at most L long is
  // within L / sqrt(3) of a corner (the circumradius of the equilateral triangle bounds that of
  // any acute one; an obtuse one's farthest point lies on its longest edge, within L / 2), plus a
  // fifth of a voxel for the curvature of a lattice triangle and the seeds' float rounding. So
  // the band's candidates need only be the voxels within the half-width plus seedReach (0.89
  // voxel) of a seed (FieldBand::nearSeeds), and a voxel whose nearest seed is further than that
  // cannot be in the band: it is not projected.
  const double seedReach = spacing / std::sqrt(3.0) + 0.2 * voxelSize;
  FieldBand band = FieldBand::nearSeeds(TargetKind::Surface, std::move(seeds.positions), voxelSize,
                                        halfWidth, seedReach / voxelSize);
  const VoxelProjector voxels(surface, blocks, seeds.points, voxelSize, halfWidth, seedReach);
  tbb::enumerable_thread_specific<LeafState> states;
  const std::size_t faceCount = surface.mesh().faceCount();
  band.setApproximantsPerWorker([&]() -> FieldBand::VoxelApproximant {
        // The factory runs on the thread that uses the function it makes (FieldBand).
        return [&voxels, state = &states.local()](const openvdb::Coord& ijk,
                                                  const Eigen::Vector3d& center) {
          return voxels(*state, ijk, center);
        };
      })
      .setEstimator(std::string(kSmoothSurfaceEstimator) + ", " + surface.sourceName() + " source")
      .setLabel("smooth surface (" + surface.sourceName() + ") of " + std::to_string(faceCount) +
                " faces" + (label.empty() ? "" : " from " + label));
  return ApproximantField::fromBand(band, options, progress);
}

}  // namespace d2vdb
