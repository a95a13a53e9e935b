// The target of a curve or surface fit, read from a file in one call: the squared-distance target
// the fitters query, its offset, and points of it to place an initial curve or surface around.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/SquaredDistanceTarget.h"
#include "d2vdb/fit/InitialSurface.h"
#include "d2vdb/fit/OffsetTarget.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/spline/BSplineCurve.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// What is fitted to the target: it decides which files are accepted and how they are sampled.
enum class FitSpline { Curve, Surface };

/// How loadFitTarget() reads a target.
struct FitTargetOptions {
  FitSpline spline = FitSpline::Curve;
  /// Non-zero: also build the offset of the target at this distance (world units; OffsetTarget.h).
  double offset = 0;
  /// Who needs the file, for loadInput()'s messages, e.g. "the target of 'd2vdb fit-curve'".
  std::string purpose = "the fit target";
  /// Progress while a field is read or built (may be empty).
  ProgressCallback progress;
};

/// A fit target as loadFitTarget() read it.
struct FitTarget {
  /// What the file held: Curve, Polylines, PointSet or Field for a curve fit; Field, Surface or
  /// PointSet for a surface fit (inputKindName() names it in reports).
  InputKind kind = InputKind::PointSet;
  /// The squared-distance target (a CurveTarget, SurfaceTarget or ApproximantField); null for a
  /// point cloud, which the point-cloud fitters take as `points`.
  std::shared_ptr<const SquaredDistanceTarget> target;
  /// The offset of `target` at FitTargetOptions::offset; null without an offset.
  std::unique_ptr<OffsetTarget> offset;
  /// A point cloud's points in file order, or points on the target: a curve or polyline sampled
  /// every 1/2000 of its length, a B-spline surface on a 101 x 101 parameter grid, a surface
  /// field's zero level set at about 200000 voxels (the footpoints of every k-th band voxel
  /// within half a voxel of it). Empty for a curve fit's field target.
  std::vector<Eigen::Vector3d> points;
  bool closed = false;  ///< a closed curve or polyline
  /// 2 for a planar curve or polyline of dimension 2 and for a point cloud with every z = 0;
  /// otherwise 3.
  int dimension = 3;
  /// Control points of a B-spline curve target, vertices of a polyline target; 0 otherwise.
  std::size_t pieces = 0;

  /// What a fitter is given: the offset when there is one, else the target (not null).
  const SquaredDistanceTarget& fitTarget() const {
    return offset ? static_cast<const SquaredDistanceTarget&>(*offset) : *target;
  }
};

/// Reads the target of a fit from `path` through loadInput() (InputFile.h):
/// - a curve fit accepts a B-spline curve, a polyline (or a slice file of exactly one polyline),
///   a point cloud and a field (any kind);
/// - a surface fit accepts a surface field (of a level set or stored), a B-spline surface and a
///   point cloud.
/// Curve and surface targets are labelled with `path` (SquaredDistanceTarget::describe()).
/// Throws InputError as loadInput() does (naming options.purpose), for a slice file without
/// exactly one polyline, a surface fit's mesh ("use a level-set or field .vdb ..."), field of
/// something other than a surface, or field without voxels on its zero level set, and for an
/// offset of a target that has none: "--offset needs a curve target ..." (curve fits: only curve
/// targets and fields of curves) or "--offset needs a field or B-spline surface target ..."
/// (surface fits: not point clouds), or one whose size reaches beyond the target's working domain
/// (the target's points grown by |offset| leave it), the messages naming the option as the d2vdb
/// command does; and as OffsetTarget does for an offset it refuses.
FitTarget loadFitTarget(const std::filesystem::path& path, const FitTargetOptions& options = {});

/// What loadFitTarget() makes of a file's content, for content already in memory: `input` as
/// loadInput() returns it (input.path labels curve and surface targets and names the target in
/// messages). Throws as loadFitTarget() does after reading.
FitTarget fitTargetFromInput(LoadedInput input, const FitTargetOptions& options = {});

/// The fit target of a field in memory, shared rather than copied (kind Field; `label` names it in
/// messages); a surface fit samples its zero level set as loadFitTarget() does. Throws
/// InputError for a null field and as loadFitTarget() does for a field target.
FitTarget fitTargetFromField(std::shared_ptr<const ApproximantField> field,
                             const std::filesystem::path& label,
                             const FitTargetOptions& options = {});

/// A generated initial curve for a fit to `target`, as `d2vdb fit-curve --init` places it:
/// shape "polyline" is the least-squares fit of the target's points (closed when `closed` or the
/// target is closed); "circle" and "ellipse" are placed around them (initialCurveAround(), scale
/// 1.2, grown by 2 |offset| over the points' extent for an offset fit). Throws InputError for
/// another shape, a target without points (a field: "pass an initial curve"), and as the
/// placing functions do.
BSplineCurve initialCurveForTarget(const FitTarget& target, const std::string& shape, int degree,
                                   int controlPoints, bool closed, double offset);

/// A generated initial surface for a fit to `target`, as `d2vdb fit-surface --init` places it:
/// shape "plane", "cylinder" (closed around the axis: in u, or in v for a ruled surface, unless
/// `layout` closes a direction) or "torus" (closed in u and v), placed around the target's points
/// by initialSurfaceAround(), cylinders and tori grown by 2 |offset| over the points' extent for
/// an offset fit. A ruled surface has layout.degreeU = 1. Throws InputError for another shape and
/// as initialSurfaceAround() does.
BSplineSurface initialSurfaceForTarget(const FitTarget& target, const std::string& shape,
                                       SurfaceLayout layout, double offset);

}  // namespace d2vdb
