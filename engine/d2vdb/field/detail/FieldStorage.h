// Internal storage of ApproximantField: compact per-voxel records addressed through a hash of
// leaf origins, and the coarse levels. Included only by the field's .cc files.
#pragma once

#include <openvdb/openvdb.h>
#include <tbb/collaborative_call_once.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/Approximant.h"

namespace d2vdb::detail {

/// Number of set bits of `bits`, inline (the portable x86-64 baseline has no popcount instruction,
/// and __builtin_popcountll then becomes a library call on every voxel look-up).
inline int countBits(std::uint64_t bits) {
  bits = bits - ((bits >> 1) & 0x5555555555555555ull);
  bits = (bits & 0x3333333333333333ull) + ((bits >> 2) & 0x3333333333333333ull);
  bits = (bits + (bits >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return static_cast<int>((bits * 0x0101010101010101ull) >> 56);
}

/// The integer nearest to `value` (ties toward +infinity), inline: std::lround is a library call
/// on the x86-64 baseline. `value` must lie well inside the int range.
inline int nearestInt(double value) {
  const double shifted = value + 0.5;
  const int truncated = static_cast<int>(shifted);
  return truncated - (static_cast<double>(truncated) > shifted ? 1 : 0);
}

/// One 8^3 block of a sparse level: its origin (index space, multiples of 8), the active-voxel
/// mask (bit (x & 7) * 64 + (y & 7) * 8 + (z & 7), OpenVDB's leaf order) and the index of its
/// first record; records of the block's active voxels follow in mask order.
struct LeafEntry {
  openvdb::Coord origin;
  std::uint32_t base = 0;
  std::array<std::uint16_t, 8> prefix{};  ///< active voxels in mask words before word w
  std::array<std::uint64_t, 8> mask{};
};

/// Open-addressing hash of LeafEntry origins (read-only after build()).
class LeafTable {
 public:
  /// Takes the entries (their `base` and `prefix` are recomputed in the given order) and returns
  /// the total number of active voxels.
  std::uint64_t build(std::vector<LeafEntry> entries);

  /// Index of the entry whose block contains voxel `ijk`, or -1.
  std::int64_t findLeaf(const openvdb::Coord& ijk) const;

  /// Record index of voxel `ijk` in entry `leaf` (which must contain it), or -1 when inactive.
  static std::int64_t recordIndex(const LeafEntry& leaf, const openvdb::Coord& ijk) {
    const int offset = ((ijk.x() & 7) << 6) | ((ijk.y() & 7) << 3) | (ijk.z() & 7);
    const int word = offset >> 6;
    const std::uint64_t bit = std::uint64_t{1} << (offset & 63);
    if ((leaf.mask[word] & bit) == 0) return -1;
    return static_cast<std::int64_t>(leaf.base) + leaf.prefix[word] +
           countBits(leaf.mask[word] & (bit - 1));
  }

  const std::vector<LeafEntry>& entries() const { return entries_; }
  std::uint64_t memoryBytes() const {
    return entries_.capacity() * sizeof(LeafEntry) + slots_.capacity() * sizeof(std::int32_t);
  }

  /// Origin of the block containing `ijk`.
  static openvdb::Coord blockOrigin(const openvdb::Coord& ijk) {
    return openvdb::Coord(ijk.x() & ~7, ijk.y() & ~7, ijk.z() & ~7);
  }

 private:
  std::size_t hash(const openvdb::Coord& origin) const;
  std::vector<LeafEntry> entries_;
  std::vector<std::int32_t> slots_;
  std::size_t slotMask_ = 0;
};

/// Voxel look-ups in one LeafTable that remember the last leaf found, for queries that move
/// little between calls. One per thread; the table must outlive it.
class LeafCursor {
 public:
  explicit LeafCursor(const LeafTable& table) : table_(&table) {}

  /// Record index of voxel `ijk`, or -1 when the table does not hold it.
  std::int64_t record(const openvdb::Coord& ijk) {
    const openvdb::Coord origin = LeafTable::blockOrigin(ijk);
    if (leaf_ < 0 || origin != origin_) {
      leaf_ = table_->findLeaf(ijk);
      origin_ = origin;
      if (leaf_ < 0) return -1;
    }
    return LeafTable::recordIndex(table_->entries()[static_cast<std::size_t>(leaf_)], ijk);
  }

 private:
  const LeafTable* table_;
  std::int64_t leaf_ = -1;
  openvdb::Coord origin_;
};

/// The 16-byte record of one band voxel (level 0). Vectors are in the field's index frame.
/// - normal: octahedral encoding of the unit normal (surface) or of the direction from the
///   footpoint toward the voxel (curves, points), two snorm16 values;
/// - angle: e1 (surface) or the unit tangent (curve) as an angle about the normal from
///   tangentBasis(normal) (encodeAngle());
/// - c0, c1: surface: k1 h, k2 h as half floats (h = voxel size); curve: kappa h as a half float
///   and the principal normal's angle about the tangent (from tangentBasis(tangent)).
struct BandRecord {
  float distance = 0.0f;  ///< world units (signed for surfaces)
  std::array<std::int16_t, 2> normal{};
  std::uint16_t angle = 0;
  std::uint16_t flags = 0;
  std::uint16_t c0 = 0;
  std::uint16_t c1 = 0;
};
static_assert(sizeof(BandRecord) == 16, "band records are 16 bytes");

/// Octahedral encoding of a unit vector into two snorm16 values, and its inverse (normalised).
std::array<std::int16_t, 2> encodeOctahedral(const Eigen::Vector3d& unit);
Eigen::Vector3d decodeOctahedral(const std::array<std::int16_t, 2>& code);

/// A deterministic orthonormal pair (b1, b2) with b1 x b2 = unit, for angle encodings.
std::array<Eigen::Vector3d, 2> tangentBasis(const Eigen::Vector3d& unit);
/// The direction of `direction` (orthogonal to `axis`, any non-zero length; zero gives code 0)
/// about `axis`, in the plane of tangentBasis(axis) = (b1, b2), as a 16-bit "diamond angle": with
/// u, v its b1, b2 components, the point (u, v) / (|u| + |v|) on the square |u| + |v| = 1, measured
/// counter-clockwise from b1 along the square's edges, one unit per quadrant, in 1/16384 units.
/// Monotonic in the true angle, with steps of 0.004-0.007 degrees, and free of trigonometry both
/// ways; decodeAngle(encodeAngle(d)) re-encodes to the same code.
std::uint16_t encodeAngle(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction);
/// The unit vector with diamond-angle code `code` about `axis` (encodeAngle()).
Eigen::Vector3d decodeAngle(const Eigen::Vector3d& axis, std::uint16_t code);

/// IEEE half-float bits of a value (OpenVDB's half), and back.
std::uint16_t encodeHalf(double value);
double decodeHalf(std::uint16_t bits);

/// A coarse level: voxel size voxelSize * 2^level; each active voxel's record is the index of
/// the band sample whose footpoint is nearest to the voxel centre. Level 1 leaves out the voxels
/// whose every query the band answers.
struct CoarseLevel {
  int level = 1;
  LeafTable table;
  std::vector<std::uint32_t> sampleOf;
};

/// Everything an ApproximantField holds.
struct FieldStorage {
  TargetKind kind = TargetKind::Surface;
  openvdb::FloatGrid::ConstPtr grid;  ///< the band's distance grid
  double voxelSize = 0.0;             ///< world
  double halfWidth = 0.0;             ///< voxels
  int coarseHalfWidth = 4;
  Eigen::Matrix3d indexToWorldLinear = Eigen::Matrix3d::Identity();  ///< h R
  Eigen::Vector3d indexToWorldOffset = Eigen::Vector3d::Zero();
  Eigen::Matrix3d worldToIndexLinear = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< index frame to world frame
  bool axisAligned = true;                                 ///< rotation is the identity
  LeafTable band;
  std::vector<BandRecord> records;
  std::vector<std::uint32_t> sampleRecords;       ///< band records serving as samples
  std::vector<Eigen::Vector3f> sampleFootpoints;  ///< their footpoints (index space)
  std::vector<CoarseLevel> coarse;                ///< read only after ensureCoarseLevels()
  tbb::collaborative_once_flag coarseOnce;
  std::atomic<bool> coarseBuilt{false};
  Eigen::AlignedBox3d domain;  ///< world
  std::string estimator;
  std::string label;
  double sampleError = 0.0;  ///< world

  Eigen::Vector3d indexToWorld(const Eigen::Vector3d& index) const {
    return indexToWorldLinear * index + indexToWorldOffset;
  }
  Eigen::Vector3d worldToIndex(const Eigen::Vector3d& world) const {
    return worldToIndexLinear * (world - indexToWorldOffset);
  }
  /// Index-frame unit vector to world frame.
  Eigen::Vector3d toWorldDirection(const Eigen::Vector3d& v) const {
    return axisAligned ? v : Eigen::Vector3d(rotation * v);
  }
  Eigen::Vector3d toIndexDirection(const Eigen::Vector3d& v) const {
    return axisAligned ? v : Eigen::Vector3d(rotation.transpose() * v);
  }

  /// The approximant of band record `record` at voxel `ijk` (world units, world frame).
  Approximant decodeBand(std::uint32_t record, const openvdb::Coord& ijk) const;
  /// The coarse approximant at index-space point `centre` from band sample `sample`.
  Approximant decodeCoarse(std::uint32_t sample, const Eigen::Vector3d& centre) const;
  /// Encodes an approximant given in the index frame (distance world, curvatures 1/world).
  BandRecord encode(const Approximant& indexFrameApproximant) const;

  /// Sets the affine maps from the grid's transform; throws InputError when it is not linear
  /// with uniform voxels.
  void setTransform(const openvdb::math::Transform& transform, const std::string& source);
  /// Builds the band table from the grid's leaves (tree order, voxels in offset order); returns
  /// the leaf pointers in the same order.
  std::vector<const openvdb::FloatGrid::TreeType::LeafNodeType*> buildBandTable();
  /// The samples (band voxels with |d| <= sqrt(3)/2 voxel) and sampleError; throws InputError when
  /// there is none (the target is not resolved at this voxel size).
  void selectSamples();
  /// The coarse levels, once (needs selectSamples()): thread-safe, callers that arrive while
  /// another builds them help with the build and return when it is done. Throws what the build
  /// throws (the next call then tries again).
  void ensureCoarseLevels(const ProgressCallback& progress);
  /// Whether ensureCoarseLevels() has completed.
  bool coarseLevelsBuilt() const { return coarseBuilt.load(std::memory_order_acquire); }
  /// Domain from the options (or the active voxels' footpoint bounds padded).
  void setDomain(const Eigen::AlignedBox3d& targetBounds, double padding,
                 const std::optional<Eigen::AlignedBox3d>& explicitDomain);

 private:
  /// Builds the coarse levels (ensureCoarseLevels() calls it once).
  void buildCoarseLevels(const ProgressCallback& progress);
  /// The cells coarse level `level` examines: every cell whose centre can lie within its reach
  /// of a sample (the rounded samples dilated), or the whole index-space domain for the top level
  /// (reach >= diagonal + voxel). Needs the samples.
  openvdb::MaskGrid::Ptr candidateCells(int level, const Eigen::AlignedBox3d& indexDomain,
                                        double diagonal) const;
};

}  // namespace d2vdb::detail
