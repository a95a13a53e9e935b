// The band of an approximant field to build: which voxels it holds and the approximant of each.
// ApproximantField::fromBand() turns one into a field; it is how curve, point-set and stored
// fields are built, and the way in for any target that can give the exact approximant at a point
// (for example a smooth surface with a closest-point projection).
#pragma once

#include <openvdb/openvdb.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "d2vdb/field/Approximant.h"

namespace d2vdb {

/// Which voxels form a field's band and how to get each one's approximant.
///
/// The voxels come from one of two named constructors:
/// - activeVoxelsOf(kind, grid): exactly the active voxels of an existing distance grid (its
///   transform, name, metadata, class and inactive values are kept; its active values become the
///   approximants' distances, on a copy when they differ). For data that already lives on a grid,
///   such as a stored field's companion grids.
/// - nearSeeds(kind, seeds, voxelSize, halfWidth, seedReach): every voxel (cubic voxels of
///   `voxelSize`, voxel (i, j, k) centred at (i, j, k) * voxelSize in world space) whose
///   approximant has |distance| < halfWidth * voxelSize, provided every point of the target lies
///   within seedReach voxels of a seed (1.5 by default: e.g. points sampled along a curve or over
///   a surface at most one voxel apart). A voxel centre v at a distance below halfWidth from the
///   target is then within R = halfWidth + seedReach voxels of a seed s, so its offset w = v -
///   round(s) from the voxel containing s lies within R of the cube [-1/2, 1/2]^3 (sum_i
///   max(|w_i| - 1/2, 0)^2 < R^2). The candidates are the voxels containing the seeds dilated by
///   the fewest 26-neighbour and 6-neighbour steps whose offsets include all those w (a rounded
///   cube; for halfWidth 3 and seedReach 1.5 three 26-neighbour steps and one 6-neighbour step,
///   637 offsets instead of the 729 of the cube of four 26-neighbour steps; for seedReach 0.89,
///   two of each, 485 offsets). The distance grid is made from the kept voxels: for surfaces a
///   level set (class GRID_LEVEL_SET, named "surface", background halfWidth * voxelSize, inactive
///   values signed by OpenVDB's signed flood fill, so the band must close around the inside); for
///   curves and points an unsigned grid named "unsigned_distance".
///
/// The approximants come from a function called once per candidate voxel (setApproximants()), or
/// from a factory that makes one such function per block of work (setApproximantsPerWorker()) when
/// the function keeps per-thread state such as grid accessors or search hints. The function gets
/// the voxel's index coordinates and its centre (world) and returns the target's Approximant taken
/// at that centre, in world units and the world frame, as Approximant.h defines it for `kind`:
/// signed distance for surfaces (negative inside) and unsigned otherwise, unit normal pointing from
/// the footpoint toward the centre (outward for surfaces), tangent (e1 for surfaces, the unit
/// tangent for curves), curvatures (k1 >= k2 for surfaces, kappa for curves, 1 / world units),
/// principal normal (curves) and flags. The field keeps distance, normal, tangent, curvatures,
/// principal normal and flags (quantised: 16-bit normal and angles, half-float curvatures times
/// the voxel size) and re-derives the footpoint as centre - distance * normal, so those must agree.
/// Curvatures beyond what the voxel size resolves are stored as given: clamp them to 1 / voxel and
/// set kFlagCurvatureClamped, as the level-set estimator does, if the SDM form must stay tame.
/// Functions are called concurrently from several threads, in no particular order; a per-worker
/// function is made by the factory on the thread that then calls it, for one block of work, and
/// is called from that thread only (so it may hold a reference to that thread's state, e.g. from
/// a tbb::enumerable_thread_specific, kept from one block to the next); the field does not depend
/// on the order or the thread count as long as the function's answer depends only on the voxel. An
/// exception thrown by the function stops the build and reaches the caller of fromBand().
///
/// Example (a smooth closed surface with an exact projection `project(x)` giving footpoint,
/// outward normal, principal curvatures and e1; `samples` points on it at most a voxel apart):
/// \code
///   FieldBand band = FieldBand::nearSeeds(TargetKind::Surface, samples, voxelSize, 3.0);
///   band.setApproximants([&](const openvdb::Coord&, const Eigen::Vector3d& centre) {
///         const SurfacePoint s = project(centre);
///         Approximant a;
///         a.kind = TargetKind::Surface;
///         a.distance = (centre - s.point).dot(s.normal);   // signed
///         a.footpoint = s.point;
///         a.normal = s.normal;
///         a.tangent = s.e1;
///         a.k1 = s.k1;
///         a.k2 = s.k2;
///         return a;
///       })
///       .setEstimator("exact projection onto the smooth surface")
///       .setLabel("smooth surface of bunny.obj")
///       .setTargetBounds(surfaceBounds);
///   const ApproximantField field = ApproximantField::fromBand(band, options, progress);
/// \endcode
class FieldBand {
 public:
  /// The approximant at one band voxel: index coordinates and centre (world) in, Approximant out.
  using VoxelApproximant =
      std::function<Approximant(const openvdb::Coord& ijk, const Eigen::Vector3d& center)>;
  /// Makes one VoxelApproximant for one worker (called once per block of voxels).
  using VoxelApproximantFactory = std::function<VoxelApproximant()>;

  /// The active voxels of `grid` (a FloatGrid with a linear transform and cubic voxels, possibly
  /// rotated, without active tiles). `kind` is the target's kind. The grid is shared, never
  /// modified. Checked by fromBand().
  static FieldBand activeVoxelsOf(TargetKind kind, openvdb::FloatGrid::ConstPtr grid);
  /// The voxels within halfWidth voxels of the target found from `seeds` (world points on or near
  /// the target, every point of the target within `seedReach` voxels of one; see the class
  /// comment). Checked by fromBand(): voxelSize > 0 and finite, 1 <= halfWidth <= 64,
  /// 0 < seedReach <= 8, at least one seed, every seed finite.
  static FieldBand nearSeeds(TargetKind kind, std::vector<Eigen::Vector3d> seeds, double voxelSize,
                             double halfWidth, double seedReach = 1.5);

  /// The per-voxel approximant; must be thread-safe (it is shared by every worker).
  FieldBand& setApproximants(VoxelApproximant approximant);
  /// A factory of per-worker approximant functions (replaces setApproximants()).
  FieldBand& setApproximantsPerWorker(VoxelApproximantFactory factory);
  /// One line saying how the approximants are obtained (stored with the field, shown by
  /// `d2vdb info`).
  FieldBand& setEstimator(std::string estimator);
  /// What the field is of, for describe() and messages (e.g. the input file's name).
  FieldBand& setLabel(std::string label);
  /// The target's bounding box (world), from which the working domain is padded
  /// (ApproximantFieldOptions). Default: the bounding box of the seeds, or of the grid's active
  /// voxel centres.
  FieldBand& setTargetBounds(const Eigen::AlignedBox3d& bounds);

  TargetKind kind() const { return kind_; }
  /// The grid whose active voxels are the band (activeVoxelsOf()), else null.
  const openvdb::FloatGrid::ConstPtr& grid() const { return grid_; }
  const std::vector<Eigen::Vector3d>& seeds() const { return seeds_; }
  /// nearSeeds() only.
  double voxelSize() const { return voxelSize_; }
  /// nearSeeds() only.
  double halfWidth() const { return halfWidth_; }
  /// nearSeeds() only: the largest distance (voxels) of a target point from its nearest seed.
  double seedReach() const { return seedReach_; }
  const VoxelApproximantFactory& approximantFactory() const { return factory_; }
  const std::string& estimator() const { return estimator_; }
  const std::string& label() const { return label_; }
  const std::optional<Eigen::AlignedBox3d>& targetBounds() const { return targetBounds_; }

 private:
  FieldBand() = default;
  TargetKind kind_ = TargetKind::Surface;
  openvdb::FloatGrid::ConstPtr grid_;
  std::vector<Eigen::Vector3d> seeds_;
  double voxelSize_ = 0.0;
  double halfWidth_ = 0.0;
  double seedReach_ = 0.0;
  VoxelApproximantFactory factory_;
  std::string estimator_;
  std::string label_;
  std::optional<Eigen::AlignedBox3d> targetBounds_;
};

}  // namespace d2vdb
