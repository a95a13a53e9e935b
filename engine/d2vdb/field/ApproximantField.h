// The squared-distance approximant field: an adaptive data structure whose cells carry local
// quadratic approximants of the squared distance function (Pottmann and Hofer 2003;
// engine/README.md, "The squared-distance approximant").
#pragma once

#include <openvdb/openvdb.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/core/ResourceBudget.h"
#include "d2vdb/field/FieldBand.h"
#include "d2vdb/field/SquaredDistanceTarget.h"

namespace d2vdb {

class CurveTarget;
namespace detail {
class FieldStorage;
}

/// Options shared by every way of building a field.
struct ApproximantFieldOptions {
  /// Working domain: the target's bounding box padded on every side by this fraction of its
  /// largest side (the default: half its size). Queries outside the domain are refused.
  double domainPadding = 0.5;
  /// An explicit working domain (world units); overrides domainPadding when set. Must contain
  /// the target's bounding box.
  std::optional<Eigen::AlignedBox3d> domain;
  /// Half-width, in voxels of their own size, of the coarse levels beyond the narrow band.
  int coarseHalfWidth = 4;
  /// Refuse fields whose estimated active voxel count (all levels) exceeds this.
  std::uint64_t maxActiveVoxels = 150'000'000;
  /// Refuse fields whose estimated memory (kApproximantBytesPerVoxel, field/VoxelBudget.h, per
  /// estimated active voxel) exceeds this many bytes, before allocating; 0 = no limit.
  std::uint64_t maxMemoryBytes = kDefaultMaxMemoryBytes;
};

/// Per-level and total sizes, for `d2vdb info` and the benchmarks.
struct FieldLevelInfo {
  int level = 0;           ///< 0 = the narrow band
  double voxelSize = 0.0;  ///< world units
  double halfWidth = 0.0;  ///< voxels of this level
  std::uint64_t activeVoxels = 0;
  std::uint64_t memoryBytes = 0;  ///< in-memory size of this level's index and records
};

struct FieldStatistics {
  TargetKind kind = TargetKind::Surface;
  std::string estimator;               ///< how the band data was obtained (one line)
  std::vector<FieldLevelInfo> levels;  ///< the band, then the coarse levels if built
  bool coarseLevelsBuilt = false;      ///< else levels, totalBytes leave them out
  std::uint64_t samples = 0;           ///< footpoint samples the coarse levels refer to
  std::uint64_t flaggedCutLocus = 0, flaggedCurvatureClamped = 0, flaggedDegraded = 0;
  std::uint64_t distanceGridBytes = 0;  ///< the FloatGrid of level 0
  std::uint64_t totalBytes = 0;         ///< everything the field holds
  /// What a dense grid over the working domain at the band's voxel size would take with the same
  /// 16 bytes per voxel for distance + approximant.
  double denseBytes = 0.0;
};

/// A narrow-band distance field whose active voxels carry the data of a local quadratic
/// approximant of d^2 (Approximant.h), plus coarser levels that answer beyond the band.
///
/// Level 0 (the band): the target's distance grid (a FloatGrid level set for surfaces, an
/// unsigned distance grid for curves and points: voxel (i,j,k) centred at (i,j,k) * voxelSize)
/// and for every active voxel one 16-byte record: normal (octahedral, 2 x 16 bit), first
/// principal direction or tangent (angle about the normal, 16 bit), flags, curvatures (2 x
/// 16-bit floats, in units of 1/voxel) and the distance (32-bit float). Records are stored
/// leaf by leaf, addressed through a hash of leaf origins and the leaf's active-voxel mask, so a
/// query costs one hash probe and one record read.
///
/// Levels 1..L (beyond the band): voxel size voxelSize * 2^level, half-width coarseHalfWidth;
/// each active voxel holds the index of the band sample (a level-0 voxel near the target) whose
/// footpoint is nearest to the voxel centre, found exactly (NearestPointTree over the samples);
/// level-1 voxels whose every query the band answers are left out. The
/// top level covers the whole working domain. A query at x uses the finest level whose stored
/// voxel nearest to x is active: in the band, that voxel's approximant moved to x to first order;
/// beyond it, the approximant of the voxel's sample seen from x (its footpoint and curvatures,
/// the normal along x - footpoint). Error bound beyond the band: see coarseDistanceErrorBound().
///
/// Construction computes the band; the coarse levels are built on the first query beyond it (or
/// by buildCoarseLevels()), with the same result. Every factory ends in the same assembly, which
/// checks the band and derives everything else from it; fromBand() is the general one (any target
/// that gives the approximant at a voxel centre), the others are shorthands for the targets d2vdb
/// knows. Queries are thread-safe; Accessor caches the last leaf per thread. Building is parallel
/// (TBB) and the result is bitwise identical for any thread count. The field's grids as standard
/// OpenVDB grids and files: io/FieldGrids.h, io/FieldFile.h.
class ApproximantField final : public SquaredDistanceTarget {
 public:
  /// Builds the field of a signed level set (any FloatGrid of class level set, from d2vdb or any
  /// OpenVDB tool: d < 0 inside, world units, uniform voxels, band half-width >= 2 voxels). The
  /// band is the grid's active voxels; their approximants come from the level set's values
  /// (footpoint interpolation of least-squares quadric fits, described in the README; the one-line
  /// summary stored with the field is kSurfaceEstimator in field/detail/SurfaceEstimator.h). The
  /// grid is shared, not modified. Throws InputError for a grid that is not a level set, has
  /// non-uniform or non-linear voxels, an empty band, a band narrower than 2 voxels, non-finite
  /// values, or an estimated size above options.maxActiveVoxels.
  static ApproximantField fromLevelSet(openvdb::FloatGrid::ConstPtr levelSet,
                                       const ApproximantFieldOptions& options = {},
                                       const ProgressCallback& progress = {});

  /// Builds the field of a band of voxels whose approximants are given (FieldBand.h): the general
  /// factory, for stored fields and any target with an exact approximant at a point. The working
  /// domain follows options (padding the band's target bounds, or options.domain, which must
  /// contain them); options.coarseHalfWidth (at least 2) sets the coarse levels. Throws InputError
  /// for bad band parameters (see FieldBand), a grid the field cannot use (non-uniform, sheared or
  /// mirrored voxels, active tiles, no active voxel), no approximant function, an approximant with
  /// non-finite values or a normal that is not a unit vector, a nearSeeds() band with more
  /// candidate voxels than options.maxActiveVoxels, a band with no voxel within sqrt(3)/2 voxel of
  /// the target, or a bad domain; rethrows what the approximant function throws.
  static ApproximantField fromBand(const FieldBand& band,
                                   const ApproximantFieldOptions& options = {},
                                   const ProgressCallback& progress = {});

  /// Builds the field of a curve: every voxel within halfWidth voxels of the curve gets the
  /// exact approximant of CurveTarget at its centre. Throws InputError for a non-positive voxel
  /// size, halfWidth < 1, or a size above the budget.
  static ApproximantField fromCurve(const CurveTarget& curve, double voxelSize, double halfWidth,
                                    const ApproximantFieldOptions& options = {},
                                    const ProgressCallback& progress = {});

  /// Builds the field of a point set: every voxel within halfWidth voxels of a point gets the
  /// nearest point (ties: the lowest index). Throws InputError for an empty set, non-finite
  /// coordinates, a non-positive voxel size, halfWidth < 1, or a size above the budget.
  static ApproximantField fromPoints(const std::vector<Eigen::Vector3d>& points, double voxelSize,
                                     double halfWidth, const ApproximantFieldOptions& options = {},
                                     const ProgressCallback& progress = {});

  ApproximantField(ApproximantField&&) noexcept;
  ApproximantField& operator=(ApproximantField&&) noexcept;
  ~ApproximantField() override;

  TargetKind kind() const override;
  Eigen::AlignedBox3d domain() const override;
  Approximant approximantAt(const Eigen::Vector3d& point) const override;
  std::vector<Approximant> approximantsAt(
      const std::vector<Eigen::Vector3d>& points) const override;
  std::string describe() const override;
  /// The band's voxel size.
  double resolvedLength() const override;

  /// A per-thread query handle: caches the last leaf it visited, so spatially coherent queries
  /// skip the hash probe. Cheap to create; must not outlive the field; not shareable between
  /// threads.
  class Accessor {
   public:
    explicit Accessor(const ApproximantField& field);
    /// As ApproximantField::approximantAt().
    Approximant approximantAt(const Eigen::Vector3d& point);
    /// The approximant stored for band voxel `ijk` (index coordinates of distanceGrid()), taken
    /// at the voxel's centre and not transported (origin = the centre), or std::nullopt when
    /// `ijk` is not a band voxel. What the field's grids (io/FieldGrids.h) hold.
    std::optional<Approximant> bandApproximant(const openvdb::Coord& ijk);
    /// The level that answered the last successful query (0 = the band).
    int lastLevel() const { return lastLevel_; }

   private:
    const ApproximantField& field_;
    std::vector<std::int64_t> cachedLeaf_;  // per level: index of the cached leaf entry or -1
    std::vector<openvdb::Coord> cachedOrigin_;
    int lastLevel_ = 0;
  };

  /// The distance grid of the band (level set for surfaces, unsigned distance otherwise). For
  /// surfaces it is a copy of the input level set whose band values are the distances the
  /// estimated footpoints imply (the input corrected by the projection onto the zero level: on the
  /// exact sphere and torus of the tests by under 0.05 voxel).
  openvdb::FloatGrid::ConstPtr distanceGrid() const;
  /// Voxel size of the band (world units).
  double voxelSize() const;
  /// Half-width of the band in voxels.
  double halfWidth() const;
  /// Number of levels (1 + coarse levels); builds the coarse levels if they are not built yet.
  int levelCount() const;
  /// Builds the coarse levels now, reporting progress. They are otherwise built on the first
  /// query beyond the band: the band's approximants, which construction computes, are all that
  /// writing the field or querying near the target needs. Thread-safe and done once; threads
  /// that query beyond the band meanwhile help with the build and wait for it.
  void buildCoarseLevels(const ProgressCallback& progress = {}) const;
  /// Whether the coarse levels have been built.
  bool coarseLevelsBuilt() const;
  /// Upper bound (world units) on how much the distance implied by a coarse-level answer at a
  /// point x, |x - footpoint|, can exceed the true distance d(x) (it is never below
  /// d(x) - sampleError()): sqrt(3) * (that level's voxel size) + sampleError(). Coarse answers
  /// are used only where d(x) exceeds about (coarseHalfWidth - 1) times that voxel size, so the
  /// relative error stays below about sqrt(3) / (coarseHalfWidth - 1).
  double coarseDistanceErrorBound(int level) const;
  /// How far a target point can be from the nearest band sample footpoint (world): the sampling
  /// error of the coarse levels, measured during construction as an upper bound
  /// (see the .cc for how).
  double sampleError() const;
  /// Sizes and counts; the coarse levels only once built (statistics() does not build them).
  FieldStatistics statistics() const;
  /// How the band's approximants were obtained (one line, as statistics().estimator).
  const std::string& estimator() const;

 private:
  explicit ApproximantField(std::unique_ptr<detail::FieldStorage> storage);
  std::unique_ptr<detail::FieldStorage> storage_;
};

}  // namespace d2vdb
