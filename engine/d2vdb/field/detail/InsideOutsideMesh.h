// A triangle mesh prepared for inside/outside decisions: welded, consistently wound, its holes
// closed by virtual caps, with adjacency, components and angle-weighted pseudonormals.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <limits>
#include <vector>

#include "d2vdb/mesh/TriangleBvh.h"
#include "d2vdb/mesh/TriangleClosestPoint.h"

namespace d2vdb::detail {

/// Which side of the surface a point lies on, seen from its closest point.
enum class SurfaceSide : std::uint8_t { front, back, unknown };

/// The mesh M with its holes closed: M + S, where S (the caps) is a cone from the centroid of
/// each loop of M's boundary. M + S is watertight (every edge traversed equally often each way),
/// so its generalised winding number W is an integer off M + S, and M's winding number is
/// w = W - w_S with w_S the caps' own (winding numbers add over triangles). For a closed M there
/// are no caps.
///
/// Preparation:
/// - vertices with identical coordinates are welded (seams of OBJ/PLY files);
/// - orientation repair: M's triangles are flipped, one edge-connected component at a time
///   (across edges shared by exactly two triangles), so that each such edge is traversed once each
///   way; a component keeps the winding of the larger part of its area; if M's signed volume is
///   then negative every triangle is flipped (an inside-out mesh). A component that cannot be
///   oriented (Moebius-like) keeps the first winding the walk gives it;
/// - the boundary (edges traversed more often one way than the other) is split into closed loops
///   and each loop is coned to the mean of its vertices;
/// - adjacency, components, normals and pseudonormals are those of M + S (Baerentzen and Aanaes,
///   "Signed distance computation using the angle weighted pseudonormal", IEEE TVCG 11(3), 2005).
struct InsideOutsideMesh {
  static constexpr std::uint32_t kNoMate = std::numeric_limits<std::uint32_t>::max();

  /// M's vertices (duplicates stay, unused), then one apex per cap loop.
  std::vector<Eigen::Vector3d> points;
  /// M's triangles (input order, welded corners, repaired winding), then the caps'.
  std::vector<TriangleIndices> triangles;
  std::uint32_t meshTriangleCount = 0;  ///< triangles [0, meshTriangleCount) are M's
  std::vector<TriangleIndices> caps;    ///< S alone (the tail of `triangles`)
  std::size_t capLoops = 0;             ///< boundary loops closed by a cap
  std::size_t boundaryEdges = 0;  ///< M's edges traversed more often one way (with multiplicity)
  /// Per half-edge 3 t + k (corner k to corner k + 1 of triangle t): the half-edge running the
  /// other way along the same edge, when exactly two triangles of M + S share the edge.
  std::vector<std::uint32_t> mate;
  std::vector<std::uint32_t> component;  ///< per triangle, edge-connected component of M + S
  std::uint32_t componentCount = 0;
  std::vector<Eigen::Vector3d> faceNormal;  ///< unit; zero for a degenerate triangle
  /// Angle-weighted pseudonormal (not normalised); zero where it does not decide a side: at a
  /// vertex whose triangles do not form one closed fan, or touch a degenerate triangle.
  std::vector<Eigen::Vector3d> vertexNormal;
  std::vector<bool> degenerate;         ///< repeated corner or |cross| <= 1e-10 * longest edge^2
  std::size_t reorientedTriangles = 0;  ///< M's triangles whose winding was reversed
  std::size_t degenerateTriangles = 0;
  /// M alone is watertight (no caps were needed).
  bool watertight = false;

  /// The side of the surface `p` lies on, given its closest point on triangle `triangle`: the sign
  /// of (p - closest) . N with N the face normal, the sum of the two face normals of an edge, or
  /// the vertex pseudonormal. Unknown where N is unusable (no mate, degenerate neighbour,
  /// non-manifold vertex) or (p - closest) is within 1e-9 radians of perpendicular to N.
  SurfaceSide side(std::uint32_t triangle, const TriangleClosestPoint& closest,
                   const Eigen::Vector3d& p) const;
};

/// Builds the prepared mesh. Corner indices must be valid. O(F log F).
InsideOutsideMesh prepareInsideOutsideMesh(std::vector<Eigen::Vector3d> points,
                                           const std::vector<TriangleIndices>& triangles);

}  // namespace d2vdb::detail
