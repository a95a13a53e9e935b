// The pieces the certified Hausdorff refinement bounds and splits: pieces of triangles (also
// segments and points) and Bézier control nets of spline pieces.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "d2vdb/measure/HausdorffShape.h"

namespace d2vdb::detail {

/// Certified upper bound of a new corner's distance to the target, which also offers the corner
/// as a witness of the lower bound (see MeshHausdorff.cc).
using CornerBound = std::function<double(const Eigen::Vector3d&)>;

/// A piece of a triangle of the `from` shape: a triangle, a segment (corner 2 = corner 1) or a
/// point (all corners equal), with certified upper bounds of its corners' distances.
struct TrianglePiece {
  std::array<Eigen::Vector3d, 3> corners;
  std::array<double, 3> cornerUpper{};
  std::uint8_t cornerCount = 3;  ///< 1 point, 2 segment, 3 triangle
  std::uint8_t depth = 0;

  /// The points whose convex hull contains the piece.
  const Eigen::Vector3d* hull() const { return corners.data(); }
  int hullCount() const { return cornerCount; }
  /// min over corners k of d(corner k) + the largest distance from corner k to the piece (at a
  /// corner, by convexity of the norm), rounded up: the 1-Lipschitz bound.
  double lipschitzUpper() const;
  bool splittable() const { return cornerCount > 1; }
  int childCount() const { return cornerCount == 3 ? 4 : 2; }
  /// The share of its primitive the piece covers.
  double share() const { return std::ldexp(1.0, -(cornerCount == 3 ? 2 : 1) * depth); }
  /// Splits at the edges' midpoints into childCount() pieces written to `children`.
  void split(TrianglePiece* children, const CornerBound& bound) const;
};

/// The primitive `triangle` of `from` as a piece, points and segments recognised by equal corners.
TrianglePiece trianglePiece(const HausdorffShape& from, const TriangleIndices& triangle,
                            const std::vector<double>& pointUpper);

/// A piece of a spline: the Bézier control net of a curve segment (degreeV = 0) or of a patch,
/// with certified upper bounds of its corners' distances (the net's corner points lie on the
/// spline: 2 for a segment, 4 for a patch, in the order (0,0), (1,0), (0,1), (1,1)).
struct NetPiece {
  std::vector<Eigen::Vector3d> controls;  ///< index a (degreeV + 1) + b
  std::array<double, 4> cornerUpper{};
  std::uint8_t degreeU = 0;
  std::uint8_t degreeV = 0;
  std::uint8_t depth = 0;

  const Eigen::Vector3d* hull() const { return controls.data(); }
  int hullCount() const { return static_cast<int>(controls.size()); }
  double lipschitzUpper() const;
  bool splittable() const { return true; }
  int childCount() const { return degreeV == 0 ? 2 : 4; }
  double share() const { return std::ldexp(1.0, -(degreeV == 0 ? 1 : 2) * depth); }
  /// The corner points (cornerCount() of them) on the spline.
  int cornerCount() const { return degreeV == 0 ? 2 : 4; }
  Eigen::Vector3d corner(int k) const;
  /// de Casteljau subdivision at the parameters' middle: two segments, or four patches ordered
  /// (low u, low v), (high u, low v), (low u, high v), (high u, high v).
  void split(NetPiece* children, const CornerBound& bound) const;
};

/// The net as a piece whose corner distances are still to be bounded (cornerUpper infinite).
NetPiece netPiece(const BezierNet& net);

}  // namespace d2vdb::detail
