// The Hausdorff distance between two shapes made of triangles (meshes, point sets, tessellated
// splines, the marching-cubes meshes of level sets), as a certified bracket.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/measure/HausdorffShape.h"

namespace d2vdb {

/// Controls of certifiedHausdorff().
struct CertifiedHausdorffOptions {
  /// Target width of each bracket: absolute (world units), or relative to the diagonal of the
  /// bounding box of both shapes when `relative` is set. Must be > 0 and finite.
  double tolerance = 1e-6;
  bool relative = true;
  /// Bound on the halvings of one primitive's edges (each level splits a triangle into four, a
  /// segment into two). Must be 1..40.
  int maxDepth = 28;
  /// Bounds on the pieces one refinement round makes: their number, and the bytes they take (a
  /// piece of a triangle about 110 bytes, of a bicubic net about 450). Beyond either, the bracket
  /// reached so far is returned with `converged` false and a warning.
  std::size_t maxPieces = 20000000;
  std::size_t maxPieceBytes = std::size_t(2) << 30;
  /// certifiedHausdorff(): refine both directed brackets to the tolerance (true), or h(B -> A)
  /// only as far as H needs it (false: its pieces settle within the tolerance of h(A -> B)'s
  /// lower bound, so bToA's bracket may be wider than the tolerance while H's is not; about half
  /// the work when h(A -> B) decides H).
  bool tightDirections = true;
  /// Called with "h(A -> B)" / "h(B -> A)" and the fraction of the bracket's gap closed.
  ProgressCallback progress;
};

/// A certified bracket of the directed Hausdorff distance h(from -> to) = max over x in from of
/// the distance from x to `to`.
struct DirectedHausdorffBracket {
  double lower = 0.0;  ///< <= h(from -> to), world units
  double upper = 0.0;  ///< >= h(from -> to)
  /// A point of `from` (up to the rounding the bracket accounts for) whose distance to `to` is
  /// at least `lower`, and its closest point on `to` (both of the shapes' triangles).
  Eigen::Vector3d witness = Eigen::Vector3d::Zero();
  Eigen::Vector3d witnessClosest = Eigen::Vector3d::Zero();
  std::size_t primitivesRefined = 0;  ///< primitives split during the branch and bound
  int deepestLevel = 0;               ///< largest subdivision depth reached
  bool converged = true;  ///< upper - lower <= the tolerance (else `warning` says why not)
  std::string warning;
  /// Certified upper bounds of the distance from each of `from`'s points to `to`, in the order
  /// of HausdorffShape::points (world units; the heat map of a mesh).
  std::vector<double> pointDistances;
};

/// The two directed brackets and the Hausdorff distance H = max of the two.
struct CertifiedHausdorff {
  DirectedHausdorffBracket aToB;
  DirectedHausdorffBracket bToA;
  double lower = 0.0;        ///< max of the two lower bounds: lower <= H(A, B)
  double upper = 0.0;        ///< max of the two upper bounds: H(A, B) <= upper
  double tolerance = 0.0;    ///< the absolute tolerance used, world units
  bool aToBIsLarger = true;  ///< whose lower bound is `lower` (ties: a -> b)
};

/// The Hausdorff distance between `a` and `b` with lower <= H <= upper and upper - lower <= the
/// tolerance (unless maxDepth or maxPieces stop the refinement first; `converged` says).
///
/// Method, for each direction (from -> to): branch and bound over the primitives of `from`.
///  - Lower bounds: certified distances from points of `from` (its points, then the corners of
///    the refined pieces) to `to`, found through a bounding-volume hierarchy over `to`.
///  - Upper bounds: the distance to one triangle t of `to` is convex, so over a piece of `from` it
///    is largest at the piece's corners: max over the piece of d(x, to) <= min over t of max over
///    the corners of d(corner, t). A cheaper bound first: d is 1-Lipschitz, so it is at most a
///    corner's distance plus the piece's extent from that corner.
///  - Refinement: in rounds, every piece whose upper bound exceeds the best lower bound plus the
///    tolerance is split at its edges' midpoints; the others are settled. A round's work is
///    independent per piece (TBB) and its results are combined in piece order, so the bracket,
///    witnesses and counts are the same for any number of threads.
///  - Rounding: every distance is a certified bound of the exact distance for the stored
///    coordinates (measure/detail/CertifiedDistance.h); the computed corners of refined pieces are
///    within 2 (depth + 1) u of the shape's coordinate magnitude of the exact ones (u = 2^-53),
///    which both bounds allow for, so the bracket holds in exact arithmetic.
///  - The shapes' approximationError (tessellated splines) widens each bracket by the sum of both
///    shapes' errors: H moves by at most that much between the shapes and their triangles.
///
///  - A shape with Bézier nets (a spline) is measured from by its nets, exactly (see
///    directedHausdorff()), and measured to by its triangles.
///
/// InputError for a shape without primitives, a non-finite coordinate, or an option out of range.
/// A progress callback may throw to stop the computation.
CertifiedHausdorff certifiedHausdorff(const HausdorffShape& a, const HausdorffShape& b,
                                      const CertifiedHausdorffOptions& options = {});

/// One direction only: h(from -> to), with `tolerance` in world units (> 0). `from` may be a
/// spline given by its Bézier nets only (HausdorffShape::nets, no triangles): its pieces are then
/// the nets' sub-patches, bounded by their control points (the convex hull property) and split
/// by de Casteljau's algorithm, so the bracket is exact for the spline and needs no tessellation.
/// `to` needs triangles.
DirectedHausdorffBracket directedHausdorff(const HausdorffShape& from, const HausdorffShape& to,
                                           double tolerance,
                                           const CertifiedHausdorffOptions& options = {});

/// Certified upper bounds of the distance from each point to the triangles of `to` (world units,
/// in order; within rounding of the exact distance): a heat map's values. InputError as above.
std::vector<double> pointDistancesTo(const HausdorffShape& to,
                                     const std::vector<Eigen::Vector3d>& points);

}  // namespace d2vdb
