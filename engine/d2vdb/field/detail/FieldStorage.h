// Everything an ApproximantField holds, assembled in one place: the band (layout and records),
// the record codec, the band samples and the coarse levels. Included only by the field's .cc files.
#pragma once

#include <openvdb/openvdb.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/Approximant.h"
#include "d2vdb/field/detail/BandLayout.h"
#include "d2vdb/field/detail/CoarseLevels.h"
#include "d2vdb/field/detail/IndexFrame.h"
#include "d2vdb/field/detail/LeafTable.h"
#include "d2vdb/field/detail/RecordCodec.h"

namespace d2vdb::detail {

/// What a field is, beside its band.
struct FieldDescription {
  TargetKind kind = TargetKind::Surface;
  std::string estimator;       ///< how the band's approximants were obtained (one line)
  std::string label;           ///< what the field is of, for describe() and messages
  Eigen::AlignedBox3d domain;  ///< the working domain (world), non-empty and finite
  double halfWidth = 0.0;      ///< of the band, in voxels (as built or as |background| / h)
  int coarseHalfWidth = 4;     ///< half-width of the coarse levels, in their voxels (>= 2)
};

/// The working domain of a field: `explicitDomain` when given (it must be a non-empty finite box
/// containing `targetBounds`), else `targetBounds` padded on every side by `padding` times its
/// largest side, and by at least one voxel. Throws InputError for a bad explicit domain or padding.
Eigen::AlignedBox3d workingDomain(const Eigen::AlignedBox3d& targetBounds, double padding,
                                  const std::optional<Eigen::AlignedBox3d>& explicitDomain,
                                  double voxelSize);

/// The storage of an ApproximantField. Every field, however it is made, is assembled by the one
/// constructor, which establishes the invariants the queries rely on:
/// - one 16-byte record per band voxel, in the order of the layout's table (LeafTable numbering);
/// - the distance grid's active values are the records' distances, bit for bit (the grid is
///   copied and rewritten when the layout's grid holds other values);
/// - the band samples are those of the records (at least one);
/// - the coarse levels are empty until ensureCoarseLevels(), then fixed.
/// Nothing is mutable afterwards except the one-time build of the coarse levels.
class FieldStorage {
 public:
  /// Assembles a field from its band layout and its records (record i for the table's i-th
  /// voxel). Throws InputError when the band holds no sample (the target is not resolved at this
  /// voxel size) and RuntimeFailure for a record count that does not match the layout or an empty
  /// or non-finite domain (a caller's bug).
  FieldStorage(const FieldDescription& description, BandLayout layout,
               std::vector<BandRecord> records);

  FieldStorage(const FieldStorage&) = delete;
  FieldStorage& operator=(const FieldStorage&) = delete;

  TargetKind kind() const { return codec_.kind(); }
  const IndexFrame& frame() const { return layout_.frame(); }
  double voxelSize() const { return layout_.frame().voxelSize(); }
  /// The band's distance grid (active values = the records' distances).
  const openvdb::FloatGrid::ConstPtr& grid() const { return layout_.grid(); }
  /// Half-width of the band in voxels.
  double halfWidth() const { return description_.halfWidth; }
  const LeafTable& band() const { return layout_.table(); }
  const std::vector<BandRecord>& records() const { return records_; }
  const BandSamples& samples() const { return samples_; }
  const Eigen::AlignedBox3d& domain() const { return description_.domain; }
  const std::string& estimator() const { return description_.estimator; }
  const std::string& label() const { return description_.label; }
  int coarseHalfWidth() const { return coarse_.halfWidth(); }

  /// The approximant of band record `record` at voxel `ijk` (world units, world frame).
  Approximant decodeBand(std::uint32_t record, const openvdb::Coord& ijk) const {
    return codec_.decodeBand(records_[record], ijk);
  }
  /// The coarse approximant at index-space point `center` from band sample `sample`.
  Approximant decodeCoarse(std::uint32_t sample, const Eigen::Vector3d& center) const {
    return codec_.decodeCoarse(records_[samples_.records[sample]],
                               samples_.footpoints[sample].cast<double>(), center);
  }

  /// Builds the coarse levels once (CoarseLevels::ensureBuilt()); thread-safe.
  void ensureCoarseLevels(const ProgressCallback& progress) const {
    coarse_.ensureBuilt(samples_, layout_.table(), progress);
  }
  bool coarseLevelsBuilt() const { return coarse_.built(); }
  /// The coarse levels, finest first (only after ensureCoarseLevels()).
  const std::vector<CoarseLevel>& coarseLevels() const { return coarse_.levels(); }

 private:
  FieldDescription description_;
  BandLayout layout_;
  std::vector<BandRecord> records_;
  RecordCodec codec_;
  BandSamples samples_;
  mutable CoarseLevels coarse_;
};

}  // namespace d2vdb::detail
