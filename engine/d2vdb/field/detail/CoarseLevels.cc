// Band samples and the coarse levels of the field (CoarseLevels.h).
#include "d2vdb/field/detail/CoarseLevels.h"

#include <openvdb/tools/Morphology.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/detail/NearestPointTree.h"

namespace d2vdb::detail {
namespace {

constexpr double kSqrt3 = 1.7320508075688772935;
/// Whether coarse level `level` is the top one: its reach (halfWidth voxels of 2^level band voxels)
/// spans the domain's index-space diagonal plus one of its voxels.
bool isTopLevel(int halfWidth, int level, double diagonal) {
  const double scale = std::ldexp(1.0, level);
  return halfWidth * scale >= diagonal + scale;
}

/// Relative rounding of a nearest-sample distance found with float arithmetic (generous).
constexpr double kSearchRounding = 1e-5;
/// More coarse levels than any domain needs (2^30 voxels across).
constexpr int kMaxCoarseLevels = 30;

/// Steps of 26-neighbour (cube) and 6-neighbour (octahedron) dilation whose combination covers
/// every lattice point within `radius` of an active one (in voxels) with the fewest extra points:
/// the combined region's support k1 |n|_1 + k2 |n|_inf must reach `radius` along the axes, the
/// face and the body diagonals; among those pairs, the smallest mean thickness
/// (1.5 k1 + 0.77 k2, the mean of |n|_1 and |n|_inf over directions) wins.
std::pair<int, int> dilationSteps(double radius) {
  const int total = static_cast<int>(std::ceil(radius));
  std::pair<int, int> best{total, 0};
  double bestCost = 1.5 * total;
  for (int cube = 0; cube <= total; ++cube) {
    const double faceDiagonal = (radius - cube * std::sqrt(2.0)) * std::sqrt(2.0);
    const double bodyDiagonal = (radius - cube * kSqrt3) * kSqrt3;
    const int octahedron = std::max({0, static_cast<int>(std::ceil(radius - cube)),
                                     static_cast<int>(std::ceil(faceDiagonal)),
                                     static_cast<int>(std::ceil(bodyDiagonal))});
    const double cost = 1.5 * cube + 0.77 * octahedron;
    if (cost < bestCost) {
      bestCost = cost;
      best = {cube, octahedron};
    }
  }
  return best;
}

/// Fills the leaves of one coarse level (one filler per thread): for every candidate cell, the
/// nearest sample to its centre, unless the cell can never answer a query.
class CoarseLeafFiller {
 public:
  CoarseLeafFiller(const NearestPointTree& tree, const std::vector<Eigen::Vector3f>& samples,
                   const LeafTable& band, const CoarseLevel* finer, int level, double reach,
                   bool top)
      : tree_(tree),
        samples_(samples),
        finer_(finer),
        level_(level),
        scale_(std::ldexp(1.0, level)),
        reach_(reach),
        top_(top),
        bandCursor_(band) {
    if (finer_ != nullptr) finerCursor_.emplace(finer_->table);
  }

  /// Fills `entry` (origin and mask) and `kept` (the kept cells' samples, in mask order) from the
  /// candidate cells of `leaf`.
  void fill(const openvdb::MaskGrid::TreeType::LeafNodeType& leaf, LeafEntry& entry,
            std::vector<std::uint32_t>& kept) {
    entry.origin = leaf.origin();
    // Lower bounds on the nearest-sample distance at the leaf's cells (index units): the distance
    // to a sample set is 1-Lipschitz, so a cell whose face neighbour is known to lie beyond the
    // reach plus one cell needs no search.
    std::array<double, 512> lower;
    lower.fill(-std::numeric_limits<double>::infinity());
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      const openvdb::Coord ijk = voxel.getCoord();
      const int offset = static_cast<int>(voxel.pos());
      if (!top_) {
        double neighbor = -std::numeric_limits<double>::infinity();
        if ((offset & 7) != 0) neighbor = std::max(neighbor, lower[offset - 1]);
        if ((offset & 56) != 0) neighbor = std::max(neighbor, lower[offset - 8]);
        if ((offset & 448) != 0) neighbor = std::max(neighbor, lower[offset - 64]);
        if (neighbor - scale_ > reach_) {
          lower[offset] = neighbor - scale_;
          continue;
        }
      }
      if (level_ == 1 && answeredByBand(ijk)) continue;
      const Eigen::Vector3d center = Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z()) * scale_;
      const std::int64_t known = knownSample(ijk);
      const std::uint32_t sample = known >= 0 ? static_cast<std::uint32_t>(known)
                                              : tree_.nearest(center.cast<float>(), hint_).index;
      hint_ = sample;
      const double distance = (samples_[sample].cast<double>() - center).norm();
      // The answer is a nearest sample up to float rounding of the search.
      lower[offset] = distance * (1.0 - kSearchRounding);
      if (!top_ && distance > reach_) continue;
      entry.mask[offset >> 6] |= std::uint64_t{1} << (offset & 63);
      kept.push_back(sample);
    }
  }

 private:
  /// Whether the band answers every query that would reach level-1 cell `ijk`: those round to one
  /// of the 27 band voxels 2 ijk + {-1, 0, 1}^3.
  bool answeredByBand(const openvdb::Coord& ijk) {
    const openvdb::Coord center(2 * ijk.x(), 2 * ijk.y(), 2 * ijk.z());
    if (bandCursor_.record(center) < 0) return false;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          if (bandCursor_.record(center + openvdb::Coord(dx, dy, dz)) < 0) return false;
        }
      }
    }
    return true;
  }

  /// A cell centre of this level is also one of the finer level's (index 2 ijk there): where that
  /// level kept it, its nearest sample is already known. -1 otherwise.
  std::int64_t knownSample(const openvdb::Coord& ijk) {
    if (!finerCursor_) return -1;
    const std::int64_t record =
        finerCursor_->record(openvdb::Coord(2 * ijk.x(), 2 * ijk.y(), 2 * ijk.z()));
    if (record < 0) return -1;
    return static_cast<std::int64_t>(finer_->sampleOf[static_cast<std::size_t>(record)]);
  }

  const NearestPointTree& tree_;
  const std::vector<Eigen::Vector3f>& samples_;
  const CoarseLevel* finer_;
  int level_;
  double scale_;
  double reach_;
  bool top_;
  LeafCursor bandCursor_;
  std::optional<LeafCursor> finerCursor_;
  /// The previous cell's answer, a near neighbour's: each search starts from it (answers are exact,
  /// so they do not depend on it).
  std::uint32_t hint_ = 0;
};

}  // namespace

BandSamples BandSamples::select(const LeafTable& band, const std::vector<BandRecord>& records,
                                double voxelSize) {
  const auto& entries = band.entries();
  std::vector<std::vector<std::uint32_t>> perLeaf(entries.size());
  const double limit = 0.5 * std::sqrt(3.0) * voxelSize;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
                        const LeafEntry& entry = entries[leaf];
                        std::uint32_t record = entry.base;
                        for (int w = 0; w < 8; ++w) {
                          const int count = countBits(entry.mask[w]);
                          for (int k = 0; k < count; ++k, ++record) {
                            if (std::abs(records[record].distance) <= limit) {
                              perLeaf[leaf].push_back(record);
                            }
                          }
                        }
                      }
                    });
  std::size_t sampleCount = 0;
  for (const auto& list : perLeaf) sampleCount += list.size();
  BandSamples samples;
  std::vector<std::uint32_t>& sampleRecords = samples.records;
  sampleRecords.reserve(sampleCount);  // exact capacity: statistics() counts it
  for (const auto& list : perLeaf) {
    sampleRecords.insert(sampleRecords.end(), list.begin(), list.end());
  }
  if (sampleRecords.empty()) {
    throw InputError("the field's band holds no voxel within " +
                     std::to_string(0.5 * std::sqrt(3.0)) +
                     " voxel of the target, so the target is not resolved at this voxel size");
  }
  // Footpoints of the samples (index space): need each record's voxel.
  std::vector<Eigen::Vector3f>& sampleFootpoints = samples.footpoints;
  sampleFootpoints.resize(sampleRecords.size());
  std::vector<std::size_t> leafStart(perLeaf.size() + 1, 0);
  for (std::size_t leaf = 0; leaf < perLeaf.size(); ++leaf) {
    leafStart[leaf + 1] = leafStart[leaf] + perLeaf[leaf].size();
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, entries.size(), 64),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
          const LeafEntry& entry = entries[leaf];
          std::size_t next = leafStart[leaf];
          std::uint32_t record = entry.base;
          for (int offset = 0; offset < 512 && next < leafStart[leaf + 1]; ++offset) {
            if ((entry.mask[offset >> 6] >> (offset & 63) & 1u) == 0) continue;
            if (record == sampleRecords[next]) {
              const Eigen::Vector3d center(entry.origin.x() + (offset >> 6),
                                           entry.origin.y() + ((offset >> 3) & 7),
                                           entry.origin.z() + (offset & 7));
              const Eigen::Vector3d normal = decodeOctahedral(records[record].normal);
              sampleFootpoints[next] =
                  (center - (records[record].distance / voxelSize) * normal).cast<float>();
              ++next;
            }
            ++record;
          }
        }
      });
  samples.error = std::sqrt(3.0) * voxelSize;
  return samples;
}

// ---- coarse levels ------------------------------------------------------------

CoarseLevels::CoarseLevels(int halfWidth, const Eigen::AlignedBox3d& domain,
                           const IndexFrame& frame)
    : halfWidth_(halfWidth), indexDomain_(frame.worldToIndex(domain.min())) {
  for (int corner = 0; corner < 8; ++corner) {
    indexDomain_.extend(
        frame.worldToIndex(domain.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner))));
  }
}

void CoarseLevels::ensureBuilt(const BandSamples& samples, const LeafTable& band,
                               const ProgressCallback& progress) {
  tbb::collaborative_call_once(once_, [&] {
    build(samples, band, progress);
    built_.store(true, std::memory_order_release);
  });
}

void CoarseLevels::build(const BandSamples& samples, const LeafTable& band,
                         const ProgressCallback& progress) {
  // Levels until one band covers the whole domain.
  const double diagonal = indexDomain_.sizes().norm();
  int levelCount = 0;
  for (int level = 1; level <= kMaxCoarseLevels; ++level) {
    levelCount = level;
    if (isTopLevel(halfWidth_, level, diagonal)) break;
  }

  // The candidate cells of every level need only the samples, so they are made while the
  // nearest-sample tree is built.
  std::optional<NearestPointTree> tree;
  std::vector<openvdb::MaskGrid::Ptr> masks(static_cast<std::size_t>(levelCount));
  tbb::parallel_invoke([&] { tree.emplace(samples.footpoints); },
                       [&] {
                         tbb::parallel_for(0, levelCount, [&](int index) {
                           masks[static_cast<std::size_t>(index)] =
                               candidateCells(index + 1, samples.footpoints, diagonal);
                         });
                       });

  levels_.clear();
  for (int level = 1; level <= levelCount; ++level) {
    const double scale = std::ldexp(1.0, level);
    const double reach = halfWidth_ * scale;
    const bool top = isTopLevel(halfWidth_, level, diagonal);
    const openvdb::MaskGrid& mask = *masks[static_cast<std::size_t>(level - 1)];
    std::vector<const openvdb::MaskGrid::TreeType::LeafNodeType*> leaves;
    for (auto leaf = mask.tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf.getLeaf());
    std::vector<LeafEntry> levelEntries(leaves.size());
    std::vector<std::vector<std::uint32_t>> levelSamples(leaves.size());
    const CoarseLevel* finer = levels_.empty() ? nullptr : &levels_.back();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        CoarseLeafFiller filler(*tree, samples.footpoints, band, finer, level,
                                                reach, top);
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          filler.fill(*leaves[i], levelEntries[i], levelSamples[i]);
                        }
                      });
    CoarseLevel coarseLevel;
    coarseLevel.level = level;
    std::vector<LeafEntry> kept;
    std::size_t keptCells = 0, keptLeaves = 0;
    for (const auto& list : levelSamples) {
      keptCells += list.size();
      keptLeaves += list.empty() ? 0 : 1;
    }
    coarseLevel.sampleOf.reserve(keptCells);  // exact capacities: statistics() counts them
    kept.reserve(keptLeaves);
    for (std::size_t i = 0; i < levelEntries.size(); ++i) {
      if (levelSamples[i].empty()) continue;
      kept.push_back(levelEntries[i]);
      coarseLevel.sampleOf.insert(coarseLevel.sampleOf.end(), levelSamples[i].begin(),
                                  levelSamples[i].end());
    }
    coarseLevel.table = LeafTable(std::move(kept));
    levels_.push_back(std::move(coarseLevel));
    masks[static_cast<std::size_t>(level - 1)].reset();  // mask is not used after this
    if (progress) progress("field: coarse levels", top ? 1.0 : std::min(0.99, reach / diagonal));
    if (top) break;
  }
}

openvdb::MaskGrid::Ptr CoarseLevels::candidateCells(int level,
                                                    const std::vector<Eigen::Vector3f>& footpoints,
                                                    double diagonal) const {
  const double scale = std::ldexp(1.0, level);
  auto mask = openvdb::MaskGrid::create(false);
  if (isTopLevel(halfWidth_, level, diagonal)) {  // the whole domain
    const Eigen::Vector3d lo = indexDomain_.min() / scale, hi = indexDomain_.max() / scale;
    const openvdb::Coord a(static_cast<int>(std::floor(lo.x())),
                           static_cast<int>(std::floor(lo.y())),
                           static_cast<int>(std::floor(lo.z())));
    const openvdb::Coord b(static_cast<int>(std::ceil(hi.x())), static_cast<int>(std::ceil(hi.y())),
                           static_cast<int>(std::ceil(hi.z())));
    mask->tree().denseFill(openvdb::CoordBBox(a, b), true, true);
    return mask;
  }
  auto accessor = mask->getAccessor();
  for (const Eigen::Vector3f& footpoint : footpoints) {
    const Eigen::Vector3d c = footpoint.cast<double>() / scale;
    accessor.setValueOn(openvdb::Coord(nearestInt(c.x()), nearestInt(c.y()), nearestInt(c.z())));
  }
  const auto [cubeSteps, octahedronSteps] = dilationSteps(halfWidth_ + 0.5 * kSqrt3);
  openvdb::tools::dilateActiveValues(mask->tree(), octahedronSteps, openvdb::tools::NN_FACE,
                                     openvdb::tools::IGNORE_TILES);
  openvdb::tools::dilateActiveValues(mask->tree(), cubeSteps, openvdb::tools::NN_FACE_EDGE_VERTEX,
                                     openvdb::tools::IGNORE_TILES);
  return mask;
}

}  // namespace d2vdb::detail
