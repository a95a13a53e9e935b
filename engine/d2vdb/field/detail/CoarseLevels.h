// The field's answers beyond the band: the band samples and the coarse levels built over them.
#pragma once

#include <openvdb/openvdb.h>
#include <tbb/collaborative_call_once.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <atomic>
#include <cstdint>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/detail/IndexFrame.h"
#include "d2vdb/field/detail/LeafTable.h"
#include "d2vdb/field/detail/RecordCodec.h"

namespace d2vdb::detail {

/// The band samples: the band voxels within sqrt(3)/2 voxel of the target, in record order, with
/// their footpoints (index space). Every target point has a voxel centre within sqrt(3)/2 voxel,
/// which is then a sample whose footpoint is within sqrt(3) voxels of that point: `error`.
struct BandSamples {
  std::vector<std::uint32_t> records;       ///< band record indices
  std::vector<Eigen::Vector3f> footpoints;  ///< index space, one per record
  double error = 0.0;                       ///< world units: sqrt(3) voxels

  /// Selects the samples of a band (its table and records, in the table's order). Throws
  /// InputError when there is none (the target is not resolved at this voxel size).
  static BandSamples select(const LeafTable& band, const std::vector<BandRecord>& records,
                            double voxelSize);
};

/// A coarse level: voxel size voxelSize * 2^level; each active voxel's record is the index of
/// the band sample whose footpoint is nearest to the voxel centre. Level 1 leaves out the voxels
/// whose every query the band answers.
struct CoarseLevel {
  int level = 1;
  LeafTable table;
  std::vector<std::uint32_t> sampleOf;
};

/// Levels 1..L of a field, built once on demand over the band samples: level l has voxels of
/// 2^l band voxels and keeps those within halfWidth of its voxels of a sample (plus, at the top
/// level, which covers the whole domain, every cell). Thread-safe: ensureBuilt() may be called
/// from any number of threads; levels() may be read once built() is true.
class CoarseLevels {
 public:
  /// Levels of half-width `halfWidth` (coarse voxels) over the world box `domain` in `frame`.
  CoarseLevels(int halfWidth, const Eigen::AlignedBox3d& domain, const IndexFrame& frame);

  /// Builds the levels once (from `samples` and the `band` table the samples index): callers that
  /// arrive while another builds them help with the build and return when it is done. The result
  /// does not depend on the thread count. Throws what the build throws (the next call then tries
  /// again).
  void ensureBuilt(const BandSamples& samples, const LeafTable& band,
                   const ProgressCallback& progress);
  /// Whether ensureBuilt() has completed.
  bool built() const { return built_.load(std::memory_order_acquire); }
  /// The levels, finest first (only after built()).
  const std::vector<CoarseLevel>& levels() const { return levels_; }
  /// Half-width of every level, in its own voxels.
  int halfWidth() const { return halfWidth_; }

 private:
  void build(const BandSamples& samples, const LeafTable& band, const ProgressCallback& progress);
  /// The cells coarse level `level` examines: every cell whose centre can lie within its reach
  /// of a sample (the rounded samples dilated), or the whole index-space domain for the top level
  /// (reach >= diagonal + voxel).
  openvdb::MaskGrid::Ptr candidateCells(int level, const std::vector<Eigen::Vector3f>& footpoints,
                                        double diagonal) const;

  int halfWidth_;
  Eigen::AlignedBox3d indexDomain_;
  std::vector<CoarseLevel> levels_;
  tbb::collaborative_once_flag once_;
  std::atomic<bool> built_{false};
};

}  // namespace d2vdb::detail
