// A triangle mesh prepared for inside/outside decisions: consistent orientation, adjacency,
// components and the angle-weighted pseudonormals of its faces, edges and vertices.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <limits>
#include <vector>

#include "d2vdb/field/detail/TriangleBvh.h"
#include "d2vdb/field/detail/TriangleClosestPoint.h"

namespace d2vdb::detail {

/// Which side of the surface a point lies on, seen from its closest point.
enum class SurfaceSide : std::uint8_t { front, back, unknown };

/// The mesh with every triangle wound consistently with its neighbours, and what the
/// closest-feature sign test needs (Baerentzen and Aanaes, "Signed distance computation using the
/// angle weighted pseudonormal", IEEE TVCG 11(3), 2005).
///
/// Orientation repair: triangles are flipped, one edge-connected component at a time (components
/// join triangles across edges shared by exactly two triangles), so that every such edge is
/// traversed once in each direction; each component keeps the winding of the larger part of its
/// area, and if the mesh's signed volume is then negative every triangle is flipped (an inside-out
/// mesh). A component that cannot be oriented (a Moebius-like strip) keeps the first winding the
/// breadth-first walk gives it; its mismatched edges lose their mate.
struct InsideOutsideMesh {
  static constexpr std::uint32_t kNoMate = std::numeric_limits<std::uint32_t>::max();

  std::vector<Eigen::Vector3d> points;
  std::vector<TriangleIndices> triangles;  ///< repaired winding
  /// Per half-edge 3 t + k (corner k to corner k + 1 of triangle t): the half-edge running the
  /// other way along the same edge, when exactly two triangles share the edge; else kNoMate.
  std::vector<std::uint32_t> mate;
  std::vector<std::uint32_t> component;  ///< per triangle, edge-connected component
  std::uint32_t componentCount = 0;
  std::vector<Eigen::Vector3d> faceNormal;  ///< unit; zero for a degenerate triangle
  /// Angle-weighted pseudonormal (not normalised); zero where it does not decide a side: at a
  /// vertex whose triangles do not form one closed fan, or touch a degenerate triangle.
  std::vector<Eigen::Vector3d> vertexNormal;
  std::vector<bool> degenerate;         ///< repeated corner or |cross| <= 1e-10 * longest edge^2
  std::size_t reorientedTriangles = 0;  ///< triangles whose winding was reversed
  std::size_t degenerateTriangles = 0;
  /// Every undirected edge is traversed equally often in both directions (counting all its
  /// triangles): the generalised winding number is then an integer off the surface.
  bool watertight = false;
  /// Every edge shared by exactly two triangles is traversed once each way after repair.
  bool consistentlyOriented = false;

  /// The side of the surface `p` lies on, given its closest point on triangle `triangle`: the sign
  /// of (p - closest) . N with N the face normal, the sum of the two face normals of an edge, or
  /// the vertex pseudonormal. Unknown where N is unusable (no mate, degenerate neighbour,
  /// non-manifold vertex) or (p - closest) is within 1e-9 radians of perpendicular to N.
  SurfaceSide side(std::uint32_t triangle, const TriangleClosestPoint& closest,
                   const Eigen::Vector3d& p) const;
};

/// Builds the repaired mesh. Corner indices must be valid. O(F log F).
InsideOutsideMesh prepareInsideOutsideMesh(std::vector<Eigen::Vector3d> points,
                                           const std::vector<TriangleIndices>& triangles);

}  // namespace d2vdb::detail
