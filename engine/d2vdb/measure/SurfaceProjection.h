// Point-surface projection: the nearest point of a tensor-product B-spline surface, for SDM II
// surface fitting (footpoints of data points on the active surface) and exact surface targets.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <vector>

#include "d2vdb/spline/BSplineSurface.h"
#include "d2vdb/spline/BezierPatch.h"

namespace d2vdb {

/// The nearest surface point found for one query point.
struct SurfaceFootpoint {
  double u = 0.0;                                   ///< parameter in u (in the domain)
  double v = 0.0;                                   ///< parameter in v
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< S(u, v)
  double squaredDistance = std::numeric_limits<double>::infinity();  ///< |S(u, v) - p|^2
  int patch = -1;  ///< index into SurfaceProjector::patches() of the piece it lies on
  /// u or v lies at an end of an open direction's domain (the distance is then to the boundary
  /// of the surface, not along its normal).
  bool onBoundary = false;
};

/// A B-spline surface prepared for repeated nearest-point queries: its Bézier patches (one per
/// non-empty knot cell) and a binary tree of their control-point boxes.
///
/// Method: patches are visited nearest box first, and a patch (or subtree) whose box is no nearer
/// than the best point so far is skipped (the box bounds the distance from below: convex hull
/// property). In each visited patch a projected Newton iteration on |S(u, v) - p|^2 over the
/// patch's parameter rectangle (Gauss-Newton where the Hessian is not positive definite, with a
/// backtracking line search; bound constraints handled by fixing a parameter at its bound while
/// the gradient pushes outward) starts from the parameters of the patch's Bézier control point
/// nearest to p, or from the hint, and runs to rounding: the footpoint satisfies
/// (S - p) . Su = (S - p) . Sv = 0 (or its bound-constrained form) to machine precision. The
/// answer is the global nearest point whenever no visited patch holds two local minima of the
/// distance, which fails only for query points near a centre of curvature of a patch (the cut
/// locus), where the best local minimum found is returned. Ties go to the patch visited first,
/// so answers are deterministic. Immutable after construction; all members are thread-safe.
class SurfaceProjector {
 public:
  /// Copies the surface and extracts its patches.
  explicit SurfaceProjector(const BSplineSurface& surface);

  /// The projected surface.
  const BSplineSurface& surface() const { return surface_; }
  /// Its Bézier patches, u-major (toBezierPatches()).
  const std::vector<BezierPatch>& patches() const { return patches_; }
  /// Box of the control points of patch `index` (contains that piece); no bounds check.
  const Eigen::AlignedBox3d& patchBounds(int index) const {
    return boxTree_[static_cast<std::size_t>(leafCount_ +
                                             leafOfPatch_[static_cast<std::size_t>(index)])];
  }

  /// The nearest point of the surface to `point`. `hint`, when given, is a footpoint of a surface
  /// with the same knot vectors (e.g. the previous iterate of a fit): its patch is solved first,
  /// from its (u, v), which gives a tight bound early. Throws InputError when `point` is not
  /// finite.
  SurfaceFootpoint nearest(const Eigen::Vector3d& point,
                           const SurfaceFootpoint* hint = nullptr) const;

  /// nearest() for every point, in parallel (TBB); `hints` is empty or holds one hint per point.
  /// Result i belongs to points[i], identical for any thread count. InputError as nearest(), for
  /// the first offending point in index order, or for a hint list of the wrong size.
  std::vector<SurfaceFootpoint> nearest(const std::vector<Eigen::Vector3d>& points,
                                        const std::vector<SurfaceFootpoint>& hints = {}) const;

 private:
  // Runs the local solve in patch `index` from (u, v) and replaces `best` when it ends nearer.
  void solveInPatch(int index, const Eigen::Vector3d& point, double u, double v,
                    SurfaceFootpoint& best) const;
  // Visits patch `index` from its nearest control point when its box can beat `best`.
  void visitPatch(int index, const Eigen::Vector3d& point, SurfaceFootpoint& best) const;

  BSplineSurface surface_;
  std::vector<BezierPatch> patches_;
  // Implicit complete binary tree of boxes: node 1 is the root, node k has children 2k and
  // 2k + 1; leaves leafCount_ + i hold the patches in Morton order of their cell (empty boxes
  // pad to a power of two). patchOfLeaf_[i] is the patch at leaf i, leafOfPatch_ the inverse.
  int leafCount_ = 1;
  std::vector<Eigen::AlignedBox3d> boxTree_;
  std::vector<int> patchOfLeaf_;
  std::vector<int> leafOfPatch_;
};

}  // namespace d2vdb
