// The interface fitting solvers query: anything that answers "which quadratic approximant of the
// squared distance holds near this point". Eigen only.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "d2vdb/field/Approximant.h"

namespace d2vdb {

/// A target shape that answers squared-distance approximant queries: the grid-based
/// ApproximantField (surfaces, curves, point sets) and the exact curve targets (CurveTarget.h).
/// All const members are thread-safe.
class SquaredDistanceTarget {
 public:
  virtual ~SquaredDistanceTarget() = default;

  /// Kind of the target.
  virtual TargetKind kind() const = 0;

  /// The region where queries are answered (world units). Throws nothing.
  virtual Eigen::AlignedBox3d domain() const = 0;

  /// The approximant valid at `point` (world). Throws InputError when `point` is not finite or
  /// lies outside domain() (the message says by how much).
  virtual Approximant approximantAt(const Eigen::Vector3d& point) const = 0;

  /// approximantAt() for every point, in parallel (TBB), result i for points[i]; identical for any
  /// thread count. Throws InputError as approximantAt() does, for the first offending point in
  /// index order. The default implementation calls approximantAt() in a parallel loop.
  virtual std::vector<Approximant> approximantsAt(const std::vector<Eigen::Vector3d>& points) const;

  /// The target's best estimate of the squared distance at `point`: the SDM form of
  /// approximantAt(point) evaluated at `point` (exact targets return the exact value). Used by
  /// line searches. Same failure behaviour as approximantAt().
  double squaredDistanceAt(const Eigen::Vector3d& point) const;

  /// A short description for messages and reports, e.g. "curve field of helix.json".
  virtual std::string describe() const = 0;

  /// Length (world units) on which the target's answers are resolved: a field's voxel size, 0
  /// for exact targets. Moves far below it cannot be told apart by the target's approximants, so
  /// a fit whose step is below a small fraction of it has converged. Throws nothing.
  virtual double resolvedLength() const { return 0.0; }
};

}  // namespace d2vdb
