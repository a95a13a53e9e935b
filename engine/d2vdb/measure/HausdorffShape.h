// Shapes as the certified Hausdorff distance sees them: triangles (some of them segments or
// points) with a certified bound on how far they lie from the shape they stand for.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "d2vdb/mesh/TriangleBvh.h"
#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/spline/BSplineCurve.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// One polynomial piece of a spline as its Bézier control net: a curve segment (degreeV = 0,
/// degreeU + 1 points) or a tensor-product patch ((degreeU + 1) (degreeV + 1) points, index
/// a (degreeV + 1) + b). The piece lies in the convex hull of its net, and the net's corner points
/// lie on it.
struct BezierNet {
  int degreeU = 1;
  int degreeV = 0;
  std::vector<Eigen::Vector3d> controls;
};

/// A compact set as a union of closed triangles over `points` (world units). A triangle may be
/// degenerate: (a, b, b) is the segment ab and (a, a, a) the point a. `approximationError` bounds
/// the Hausdorff distance between these triangles and the shape they were made from (0 when they
/// are that shape: a mesh, a point set); a tessellated spline's bound is certified from its
/// control points (hausdorffShapeOfSurface()).
struct HausdorffShape {
  std::vector<Eigen::Vector3d> points;
  std::vector<TriangleIndices> triangles;
  double approximationError = 0.0;  ///< world units, >= 0
  std::string description;          ///< what the triangles are, for reports: "mesh", ...
  /// A spline's Bézier pieces (empty for meshes and points): the exact shape, which the Hausdorff
  /// refinement splits when the shape is the one measured from (the triangles, which may then be
  /// absent, serve when it is measured to).
  std::vector<BezierNet> nets;
};

/// The mesh's triangles (positions converted to double, exactly). InputError for a mesh without
/// triangles, an index out of range or a non-finite position.
HausdorffShape hausdorffShapeOfMesh(const TriangleMesh& mesh);

/// One point primitive per point. InputError for no points or a non-finite one.
HausdorffShape hausdorffShapeOfPoints(const std::vector<Eigen::Vector3d>& points);

/// The curve as a polyline of segments, `maxError` (world units, > 0) from the curve: each
/// Bézier piece of degree p with control points P_k is cut into n equal parameter steps h = 1/n
/// with h^2 / 8 max_k |p (p - 1) (P_k+2 - 2 P_k+1 + P_k)| <= maxError (the error of linear
/// interpolation, |f - I f| <= h^2 / 8 max |f''|, with the second derivative inside the convex
/// hull of its own control points), plus the rounding of the evaluation. InputError for a
/// non-finite or negative maxError, or one that would need more than 5e7 segments. `nets` holds
/// the Bézier segments; maxError = 0 gives the nets alone (no segments).
HausdorffShape hausdorffShapeOfCurve(const BSplineCurve& curve, double maxError);

/// The surface as triangles, `maxError` (world units, > 0) from it: each Bézier patch of degrees
/// (p, q) is cut into an nu x nv grid of parameter cells, each split into two triangles, with
/// (hu^2 Muu + 2 hu hv Muv + hv^2 Mvv) / 2 <= maxError, where Muu, Muv, Mvv bound the second
/// derivatives by their control points (p (p - 1) |second differences in u|, ...): Taylor's
/// theorem at the point against each corner of its triangle, the gradient terms cancelling in the
/// barycentric combination. InputError as hausdorffShapeOfCurve(), at 5e7 triangles; `nets` holds
/// the Bézier patches, and maxError = 0 gives them alone.
HausdorffShape hausdorffShapeOfSurface(const BSplineSurface& surface, double maxError);

/// The diagonal of the bounding box of both shapes' points (world units; 0 for two equal points).
double combinedDiagonal(const HausdorffShape& a, const HausdorffShape& b);

}  // namespace d2vdb
